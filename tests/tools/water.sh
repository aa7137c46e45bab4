# Water on the terrain as a user makes it: a lake polygon rasterised with
# gdal_rasterize, or a water level, through terrainprep into the
# heightfield; cloudrender shows water where the mask says, and a GMT
# palette colours the land.
. "$TOP/tests/tools/lib.sh"
plan 4
TP="$BIN/terrainprep"
CR="$BIN/cloudrender"
WX="$BIN/wxinterp"
FAST="--quality low --noise-size 32 -q"

# px FILE.png X Y: "r g b" of one pixel
px() { pngtopnm "$1" | pnmcut "$2" "$3" 1 1 | pnmtoplainpnm | tail -n 1 | xargs; }
# the pixels of two renders that differ: "count meanY_a meanY_b mean(B-G)_a mean(B-G)_b"
differing() {
	pngtopnm "$1" | pnmtoplainpnm | tail -n +4 | tr -s ' \n' '\n\n' | grep -v '^$' >"$T/a.txt"
	pngtopnm "$2" | pnmtoplainpnm | tail -n +4 | tr -s ' \n' '\n\n' | grep -v '^$' >"$T/b.txt"
	paste "$T/a.txt" "$T/b.txt" | awk '{ i = (NR - 1) % 3; a[i] = $1; b[i] = $2
		if (i == 2 && (a[0] != b[0] || a[1] != b[1] || a[2] != b[2])) { n++
			ya += 0.2126 * a[0] + 0.7152 * a[1] + 0.0722 * a[2]
			yb += 0.2126 * b[0] + 0.7152 * b[1] + 0.0722 * b[2]
			ba += a[2] - a[1]; bb += b[2] - b[1] } }
		END { if (n == 0) print 0, 0, 0, 0, 0; else printf "%d %.1f %.1f %.1f %.1f\n", n, ya / n, yb / n, ba / n, bb / n }'
}
gt() { awk -v a="$1" -v b="$2" 'BEGIN { exit !(a > b) }'; }

# the synthetic Bern DEM (EPSG:2056, 50 m, 400 x 400 from 2590000,1210000)
# and a 3.7 x 1.8 km lake north of the Gurten, rasterised on its grid
if "$TOP/scripts/make-bern-dem" -r 50 "$T/dem.tif" >/dev/null 2>&1; then
cat >"$T/lake.geojson" <<'GJ'
{"type":"FeatureCollection","crs":{"type":"name","properties":{"name":"urn:ogc:def:crs:EPSG::2056"}},
"features":[{"type":"Feature","properties":{},"geometry":{"type":"Polygon","coordinates":
[[[2598500,1197600],[2602200,1197600],[2602200,1199400],[2598500,1199400],[2598500,1197600]]]}}]}
GJ
gdal_rasterize -q -burn 1 -tr 50 50 -te 2590000 1190000 2610000 1210000 -ot Byte \
	-a_nodata 0 "$T/lake.geojson" "$T/lake.tif" 2>"$T/err"
"$WX" --template --set layer.low.coverage=0 --set layer.high.coverage=0 >"$T/clear.json"

begin terrainprep_stores_the_water_of_a_rasterised_lake
run "$TP" -q --water-mask "$T/lake.tif" -o "$T/lake.exr" "$T/dem.tif"; expect_rc 0
# the lake's samples as GDAL counts them: 74 x 36 cells of 50 m
want=$(gdal_translate -q -of XYZ "$T/lake.tif" /vsistdout/ | awk '$3 == 1' | wc -l)
[ "$want" -eq 2664 ] || bad "gdal_rasterize burnt $want cells, 74 x 36 = 2664 expected"
run "$TP" --info "$T/lake.exr" --json; expect_rc 0
got=$(jq '.water.samples' "$T/out")
[ "$got" = "$want" ] || bad "--info: $got water samples, the mask has $want"
jq -e '.water.mask == "lake.tif"' "$T/out" >/dev/null || bad "--info does not name the mask"
jq -e '.water.channel == "W" and .water.samples == '"$want" "$T/lake.json" >/dev/null ||
	bad "the sidecar lacks water: $(jq -c .water "$T/lake.json")"
# a mask of two bands is its first: band 2 water everywhere changes nothing
gdal_translate -q -a_nodata none -scale 0 1 1 1 "$T/lake.tif" "$T/ones.tif"
gdalbuildvrt -q -separate "$T/two.vrt" "$T/lake.tif" "$T/ones.tif"
gdal_translate -q "$T/two.vrt" "$T/two.tif"
run "$TP" -q --water-mask "$T/two.tif" -o "$T/two.exr" "$T/dem.tif"; expect_rc 0
run "$TP" --info "$T/two.exr" --json; expect_rc 0
[ "$(jq '.water.samples' "$T/out")" = "$want" ] ||
	bad "a two-band mask: $(jq '.water.samples' "$T/out") water samples, band 1 has $want"
# a heightfield without water reads as before
run "$TP" -q -o "$T/plain.exr" "$T/dem.tif"; expect_rc 0
jq -e 'has("water") | not' "$T/plain.json" >/dev/null || bad "water in a plain sidecar"
run "$TP" --info "$T/plain.exr"; expect_rc 0; expect_out "  samples: 0"
end

begin terrainprep_water_level_floods_to_a_flat_surface
run "$TP" -q --water-level 560 -o "$T/lvl.exr" "$T/dem.tif"; expect_rc 0
want=$(gdal_translate -q -of XYZ "$T/dem.tif" /vsistdout/ | awk '$3 <= 560' | wc -l)
run "$TP" --info "$T/lvl.exr" --json; expect_rc 0
[ "$(jq '.water.samples' "$T/out")" = "$want" ] || bad "$(jq '.water.samples' "$T/out") water samples, GDAL counts $want at or below 560 m"
[ "$(jq '.height_m.min' "$T/out")" = "560" ] || bad "the flooded surface's lowest height is $(jq '.height_m.min' "$T/out"), not the level 560"
run "$TP" -q --water-level 560 -o "$T/lvl.r16" "$T/dem.tif"; expect_rc 2; expect_err "EXR heightfields only"
run "$TP" -q --water-mask "$T/nope.tif" -o "$T/x.exr" "$T/dem.tif"; expect_rc 1; expect_err "--water-mask"
expect_no_file "$T/x.exr"
end

begin cloudrender_shows_water_where_the_mask_says
# straight down from 3 km over the lake's centre, 90 deg: the lake spans
# columns 0.19..0.81 and rows 0.34..0.66 of the frame (north up)
CAM="--camera 46.93759,7.44323,3600 --look 0,-90 --fov 90 --size 64x64"
run "$CR" --wx "$T/clear.json" --terrain "$T/lake.exr" $CAM -o "$T/top_w.png" -v $FAST; expect_rc 0
expect_err " water"
run "$CR" --wx "$T/clear.json" --terrain "$T/plain.exr" $CAM -o "$T/top_l.png" $FAST; expect_rc 0
set -- $(px "$T/top_w.png" 32 32); [ "$3" -gt "$2" ] || bad "lake centre is not blue: $*"
set -- $(px "$T/top_l.png" 32 32); [ "$2" -gt "$3" ] || bad "without water the centre is not green: $*"
for xy in "32 16" "32 48" "4 32" "60 32" "4 4"; do   # outside the lake: land
	[ "$(px "$T/top_w.png" $xy)" = "$(px "$T/top_l.png" $xy)" ] || bad "pixel $xy outside the lake changed"
done
for xy in "16 32" "48 32" "32 24" "32 40"; do        # inside: water
	[ "$(px "$T/top_w.png" $xy)" != "$(px "$T/top_l.png" $xy)" ] || bad "pixel $xy inside the lake is land"
done
# Fresnel: from above the water reflects 2 % and is darker than the land;
# at the grazing angles seen from the Gurten it mirrors the bright sky
set -- $(differing "$T/top_w.png" "$T/top_l.png")
gt "$1" 500 || bad "only $1 water pixels from above"
gt "$3" "$2" || bad "from above the water (Y $2) is not darker than the land (Y $3)"
gt "$4" 0 && gt 0 "$5" || bad "from above: water B-G $4, land B-G $5"
run "$CR" --wx "$T/clear.json" --terrain "$T/lake.exr" --view gurten --size 160x90 -o "$T/g_w.png" $FAST
run "$CR" --wx "$T/clear.json" --terrain "$T/plain.exr" --view gurten --size 160x90 -o "$T/g_l.png" $FAST
set -- $(differing "$T/g_w.png" "$T/g_l.png")
gt "$1" 300 || bad "only $1 water pixels from the Gurten"
gt "$2" "$3" || bad "at grazing angles the water (Y $2) is not brighter than the land (Y $3)"
end

begin cloudrender_terrain_cpt_colours_by_height
printf '# COLOR_MODEL = RGB\n0\t255/0/0\t700\t255/0/0\n700\t0/0/255\t2000\t0/0/255\n' >"$T/p.cpt"
CAM="--camera 46.93759,7.44323,3600 --look 0,-90 --fov 90 --size 64x64"
run "$CR" --wx "$T/clear.json" --terrain "$T/plain.exr" --terrain-cpt "$T/p.cpt" $CAM -o "$T/cpt.png" $FAST
expect_rc 0
# the land there lies below 700 m: red
set -- $(px "$T/cpt.png" 32 32); [ "$1" -gt $(($2 + $3)) ] || bad "land below 700 m is not red: $*"
printf '0 255/0/0 700 255/0/0\n800 0/0/255 500 0/0/255\n' >"$T/bad.cpt"
run "$CR" --terrain "$T/plain.exr" --terrain-cpt "$T/bad.cpt" -o "$T/x.png" $FAST
expect_rc 1; expect_err "bad.cpt: line 2:"; expect_no_file "$T/x.png"
run "$CR" --terrain-cpt "$T/p.cpt" -o "$T/x.png" $FAST; expect_rc 2; expect_err "--terrain-cpt needs --terrain"
end
else
	skip terrainprep_stores_the_water_of_a_rasterised_lake "scripts/make-bern-dem failed (gdal-bin?)"
fi
