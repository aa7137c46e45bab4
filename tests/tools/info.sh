# terrainprep --info and noisebake --info: one style (labelled lines, or
# --json), figures checked against GDAL's gdalinfo on the same grid.
. "$TOP/tests/tools/lib.sh"
plan 3
TP="$BIN/terrainprep"
NB="$BIN/noisebake"
DEM="${DATA:-}/dem"

# the value after "label:" on the first line that has it
field() { sed -n "s/^ *$1: *//p" "$T/out" | head -n 1; }
# |a - b| <= tol
near() { awk -v a="$1" -v b="$2" -v t="$3" 'BEGIN { d = a - b; if (d < 0) d = -d; exit !(d <= t) }'; }

begin terrainprep_info_agrees_with_gdalinfo_stats
if [ -f "$DEM/n43.dt0" ]; then
	run "$TP" -q -o "$T/n43.exr" "$DEM/n43.dt0"; expect_rc 0
	mkdir -p "$T/tif"; run "$TP" -q -o "$T/tif/n43.tif" "$DEM/n43.dt0"; expect_rc 0
	GDAL_PAM_ENABLED=NO gdalinfo -stats "$T/tif/n43.tif" >"$T/gi" 2>&1 || bad "gdalinfo failed"
	gmin=$(sed -n 's/.*Minimum=\([-0-9.]*\), Maximum=\([-0-9.]*\), Mean=\([-0-9.]*\).*/\1/p' "$T/gi")
	gmax=$(sed -n 's/.*Minimum=\([-0-9.]*\), Maximum=\([-0-9.]*\), Mean=\([-0-9.]*\).*/\2/p' "$T/gi")
	gmean=$(sed -n 's/.*Minimum=\([-0-9.]*\), Maximum=\([-0-9.]*\), Mean=\([-0-9.]*\).*/\3/p' "$T/gi")
	gpx=$(sed -n 's/^Pixel Size = (\([0-9.]*\),.*/\1/p' "$T/gi")
	run "$TP" --info "$T/n43.exr"; expect_rc 0
	# gdalinfo's "Size is 103, 140" (GDAL-NOTES: the default grid of n43.dt0 in UTM 17N)
	grep -q "^Size is 103, 140" "$T/gi" || bad "gdalinfo: not the 103x140 grid of GDAL-NOTES"
	expect_out "size: 103 x 140 samples"
	expect_out "crs: EPSG:32617"
	near "$(field min | cut -d' ' -f1)" "$gmin" 0.001 || bad "min $(field min) != gdalinfo $gmin"
	near "$(field max | cut -d' ' -f1)" "$gmax" 0.001 || bad "max $(field max) != gdalinfo $gmax"
	near "$(field mean | cut -d' ' -f1)" "$gmean" 0.001 || bad "mean $(field mean) != gdalinfo $gmean"
	near "$(field 'pixel size' | cut -d' ' -f1)" "$gpx" 0.001 || bad "pixel size $(field 'pixel size') != $gpx"
	# voids: the warp to UTM leaves the corners outside the data; filled
	expect_out "count: 476 (filled)"
	expect_out "policy: fill=nearest; source nodata -32767"
	# bounds: gdalinfo's WGS84 extent of the outer corners, within 1e-4 deg (11 m)
	GDAL_PAM_ENABLED=NO gdalinfo -json "$T/tif/n43.tif" >"$T/gj" 2>/dev/null
	for k in south north west east; do
		case $k in
		south) ref=$(jq '[.wgs84Extent.coordinates[0][][1]] | min' "$T/gj") ;;
		north) ref=$(jq '[.wgs84Extent.coordinates[0][][1]] | max' "$T/gj") ;;
		west) ref=$(jq '[.wgs84Extent.coordinates[0][][0]] | min' "$T/gj") ;;
		east) ref=$(jq '[.wgs84Extent.coordinates[0][][0]] | max' "$T/gj") ;;
		esac
		near "$(field $k)" "$ref" 0.0001 || bad "$k $(field $k) != gdalinfo $ref"
	done
	# true metres: the north edge's great circle (haversine, R 6371 km, on
	# gdalinfo's outer corners) over the width, within 0.5 %
	ref=$(jq -r '.wgs84Extent.coordinates[0] | "\(.[0][1]) \(.[0][0]) \(.[3][1]) \(.[3][0])"' "$T/gj" |
		awk '{ r = atan2(0, -1) / 180; a = sin(($3 - $1) * r / 2)^2 + cos($1 * r) * cos($3 * r) * sin(($4 - $2) * r / 2)^2;
		       printf "%.3f", 2 * 6371000 * atan2(sqrt(a), sqrt(1 - a)) / 103 }')
	gx=$(field 'ground pixel size' | cut -d' ' -f1)
	near "$gx" "$ref" "$(awk -v r="$ref" 'BEGIN { print r * 0.005 }')" || bad "ground pixel $gx != $ref"
	# --json: the same facts, machine-readable
	run "$TP" --info "$T/n43.exr" --json; expect_rc 0
	jq -e '.size == [103, 140] and .crs == "EPSG:32617" and .voids.count == 476' "$T/out" >/dev/null ||
		bad "--json lacks size/crs/voids: $(head -c 300 "$T/out")"
	jm=$(jq '.height_m.mean' "$T/out")
	near "$jm" "$gmean" 0.001 || bad "--json mean $jm != $gmean"
	end
else
	skip terrainprep_info_agrees_with_gdalinfo_stats "no $DEM/n43.dt0 (shared data absent)"
fi

begin terrainprep_info_refuses_what_is_no_heightfield
run "$TP" --info "$T/none.exr"; expect_rc 1; expect_err "terrainprep: "
run "$TP" --info "$T/none.exr" -o "$T/x.exr"; expect_rc 2; expect_err "--info reads a heightfield"
run "$TP" --json -o "$T/x.exr" dem.tif; expect_rc 2; expect_err "--json goes with --info"
end

begin noisebake_info_shares_the_style_and_json
run "$NB" -s 8 --seed 7 -o "$T/v.exr" -q; expect_rc 0
run "$NB" --info "$T/v.exr"; expect_rc 0
expect_out "size: 8 x 8 x 8"; expect_out "seed: 7"; expect_out "channels:"
expect_out "    period: 4 x 4 x 4 cells"
run "$NB" --info "$T/v.exr" --json; expect_rc 0
jq -e '.size == [8, 8, 8] and .seed == 7 and .channels.B.period_cells == [8, 8, 8]
	and (.channels.R.min <= .channels.R.mean) and (.channels.R.mean <= .channels.R.max)' "$T/out" >/dev/null ||
	bad "--json: $(head -c 300 "$T/out")"
run "$NB" -s 8 --json -o "$T/w.exr"; expect_rc 2; expect_err "--json goes with --info"
end
