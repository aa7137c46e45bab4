# terrainprep as a user runs it, on GDAL's own test DEMs (DATA/dem; the
# cases that need them skip when that folder is absent; gdal-bin, which
# make deps installs, missing is a failure).
. "$TOP/tests/tools/lib.sh"
plan 14
TP="$BIN/terrainprep"
DEM="${DATA:-}/dem"
have_dem() { [ -r "$DEM/$1" ]; }
# need_gdal: the case fails (never skips) when a gdal-bin program is missing
need_gdal() {
	for g in gdal_translate gdalbuildvrt gdalinfo gdallocationinfo gdalwarp; do
		command -v $g >/dev/null 2>&1 || bad "$g is missing (make deps installs gdal-bin)"
	done
}
# json_num FILE KEY: the first number after "KEY": in a sidecar
json_num() { sed -n "s/.*\"$2\":[[:space:]]*\(-\{0,1\}[0-9.e+-]*\).*/\1/p" "$1" | head -n 1; }
# near A B TOL: |A - B| <= TOL
near() { awk -v a="$1" -v b="$2" -v t="$3" 'BEGIN { d = a - b; exit !(a != "" && (d < 0 ? -d : d) <= t) }'; }

begin terrainprep_n43_to_utm17_at_1000m
if have_dem n43.dt0; then
	run "$TP" "$DEM/n43.dt0" --res 1000 -o "$T/n43.exr" -v
	expect_rc 0; expect_file "$T/n43.exr"; expect_file "$T/n43.json"
	expect_err "83x113 samples of 1000x1000 m, EPSG:32617, heights 75..456.179 m"
	j="$T/n43.json"
	[ "$(json_num "$j" width)" = 83 ] || bad "width $(json_num "$j" width)"
	[ "$(json_num "$j" height)" = 113 ] || bad "height $(json_num "$j" height)"
	[ "$(json_num "$j" epsg)" = 32617 ] || bad "epsg $(json_num "$j" epsg)"
	[ "$(json_num "$j" min)" = 75 ] || bad "min $(json_num "$j" min)"
	near "$(json_num "$j" max)" 456.18 0.01 || bad "max $(json_num "$j" max)"
	grep -q '"row_order":	"north-up"' "$j" || bad "no north-up row order"
	grep -q '"driver":	"DTED"' "$j" || bad "driver not recorded"
	grep -q '"policy":	"fill=nearest; source nodata -32767"' "$j" || bad "nodata policy"
	grep -q '"resampling":	"bilinear"' "$j" || bad "resampling"
	rm -f "$T/out" "$T/err"; expect_only_files "$T" 2
	rm -f "$T/n43.exr" "$T/n43.json"
	end
else
	skip terrainprep_n43_to_utm17_at_1000m "$DEM/n43.dt0 is absent"
fi

begin terrainprep_input_without_crs_needs_s_srs
if have_dem nodata_float.asc; then
	run "$TP" "$DEM/nodata_float.asc" -o "$T/nf.exr"
	expect_rc 1
	expect_err "terrainprep: $DEM/nodata_float.asc has no coordinate reference system"
	expect_err "name it with --s-srs, e.g. --s-srs EPSG:"
	expect_no_file "$T/nf.exr"; expect_no_file "$T/nf.json"
	run "$TP" "$DEM/nodata_float.asc" --s-srs EPSG:32611 -o "$T/nf.exr" -v
	expect_rc 0; expect_err "5x5 samples of 60x60 m, EPSG:32611, heights 107..156 m"
	[ "$(json_num "$T/nf.json" voids)" = 0 ] || bad "voids in nodata_float.asc"
	run "$TP" "$DEM/nodata_float.asc" --s-srs EPSG:nonsense -o "$T/nf2.exr"
	expect_rc 2; expect_err "--s-srs: 'EPSG:nonsense' is not a coordinate reference system"
	rm -f "$T"/nf*
	end
else
	skip terrainprep_input_without_crs_needs_s_srs "$DEM/nodata_float.asc is absent"
fi

begin terrainprep_fill_modes
if have_dem withnodata.asc ; then
	need_gdal
	w="$DEM/withnodata.asc"
	# the upper-left sample is the void (-999); the others are 0
	for mode in nearest value=123.5 none; do
		run "$TP" "$w" --s-srs EPSG:32611 --fill "$mode" -o "$T/w-$mode.tif"
		expect_rc 0
		grep -q "\"policy\":	\"fill=$mode; source nodata -999\"" "$T/w-$mode.json" ||
			bad "$mode: policy not recorded"
		[ "$(json_num "$T/w-$mode.json" voids)" = 1 ] || bad "$mode: voids"
	done
	v() { gdal_translate -q -of XYZ "$1" /vsistdout/ | head -n 1 | awk '{ print $3 }'; }
	[ "$(v "$T/w-nearest.tif")" = 0 ] || bad "nearest filled with $(v "$T/w-nearest.tif")"
	[ "$(v "$T/w-value=123.5.tif")" = 123.5 ] || bad "value filled with $(v "$T/w-value=123.5.tif")"
	[ "$(json_num "$T/w-value=123.5.json" max)" = 123.5 ] || bad "value: max not 123.5"
	gdalinfo "$T/w-none.tif" | grep -q 'NoData Value=nan' || bad "none: no NaN nodata"
	run "$TP" "$w" --s-srs EPSG:32611 --fill value -o "$T/w0.tif"
	expect_rc 0; [ "$(v "$T/w0.tif")" = 0 ] || bad "bare value did not fill 0"
	run "$TP" "$w" --s-srs EPSG:32611 --fill none -o "$T/w-none.exr"
	expect_rc 0
	# the void stays a void (NaN) in the EXR, the rest is the data's 0
	[ "$("$HELPERS/exrpixel" "$T/w-none.exr" 0 0 Y | sed -n 2p)" = nan ] ||
		bad "--fill none: the void reads back as $("$HELPERS/exrpixel" "$T/w-none.exr" 0 0 Y 2>&1 | tail -n 1)"
	[ "$("$HELPERS/exrpixel" "$T/w-none.exr" 1 1 Y | sed -n 2p)" = 0 ] || bad "--fill none changed a sample"
	run "$TP" "$w" --s-srs EPSG:32611 --max-void-fraction 0.2 -o "$T/w-many.exr"
	expect_rc 1; expect_err "25.0% of the output samples are voids"
	expect_err "more than --max-void-fraction 0.2"; expect_no_file "$T/w-many.exr"
	run "$TP" "$w" --s-srs EPSG:32611 --fill none -o "$T/w.r16"
	expect_rc 2; expect_err "r16 cannot hold voids"
	run "$TP" "$w" --s-srs EPSG:32611 --src-nodata none -o "$T/w-raw.exr"
	expect_rc 0; [ "$(json_num "$T/w-raw.json" min)" = -999 ] || bad "--src-nodata none"
	rm -f "$T"/w*
	end
else
	skip terrainprep_fill_modes "$DEM/withnodata.asc is absent"
fi

begin terrainprep_reads_standard_input
if have_dem n43.dt0 ; then
	need_gdal
	run "$TP" - -o "$T/si.exr" --res 1000 -v <"$DEM/n43.dt0"
	expect_rc 0; expect_err "83x113 samples"
	grep -q '"file":	"stdin (standard input)"' "$T/si.json" || bad "source not named"
	# SRTM takes its position from the file name: --stdin-name
	gdal_translate -q -of SRTMHGT -outsize 1201 1201 "$DEM/n43.dt0" "$T/N43W080.hgt" 2>/dev/null
	run "$TP" - -o "$T/srtm.exr" --res 1000 <"$T/N43W080.hgt"
	expect_rc 1; expect_err "terrainprep: \`standard input' not recognized"
	run "$TP" - --stdin-name N43W080.hgt -o "$T/srtm.exr" --res 1000 -v <"$T/N43W080.hgt"
	expect_rc 0; expect_err "83x113 samples of 1000x1000 m, EPSG:32617, heights 75.."
	expect_err "resampling average"
	rm -f "$T"/si.* "$T"/srtm.* "$T/N43W080.hgt"
	end
else
	skip terrainprep_reads_standard_input "$DEM/n43.dt0 is absent"
fi

begin terrainprep_mosaics_tiles
if have_dem n43.dt0 ; then
	need_gdal
	# the west and east halves (sharing a column): the grid and heights
	# gdalwarp gives for the two (84x114, 75..456.45: the union of the
	# halves' suggested extents is one pixel wider than the whole tile's)
	gdal_translate -q -srcwin 0 0 61 121 "$DEM/n43.dt0" "$T/west.tif"
	gdal_translate -q -srcwin 60 0 61 121 "$DEM/n43.dt0" "$T/east.tif"
	run "$TP" "$T/west.tif" "$T/east.tif" --res 1000 -o "$T/m.exr" -v
	expect_rc 0; expect_err "84x114 samples of 1000x1000 m, EPSG:32617, heights 75..456.45 m"
	run "$TP" "$T/west.tif" "$T/east.tif" --size 100 -o "$T/m.exr" -v
	expect_rc 0; expect_err "73x100 samples of 1135.45x1135.45 m"  # as gdalwarp -ts 0 100
	grep -q '"file":	"'"$T"'/west.tif, '"$T"'/east.tif"' "$T/m.json" || bad "sources not listed"
	rm -f "$T"/west.tif "$T"/east.tif "$T"/m.*
	end
else
	skip terrainprep_mosaics_tiles "$DEM/n43.dt0 is absent"
fi

begin terrainprep_uses_the_first_band_of_many
if have_dem n43.dt0 ; then
	need_gdal
	# band 1 the tile, band 2 the tile 1000 m higher: the heights are
	# band 1's (75..456.179 m at 1000 m, as gdalwarp -b 1 gives them)
	gdal_translate -q -of GTiff "$DEM/n43.dt0" "$T/b1.tif"
	gdal_translate -q -scale 0 1 1000 1001 -ot Float32 "$DEM/n43.dt0" "$T/b2.tif"
	gdalbuildvrt -q -separate "$T/two.vrt" "$T/b1.tif" "$T/b2.tif"
	gdal_translate -q "$T/two.vrt" "$T/two.tif"
	[ "$(gdalinfo "$T/two.tif" | grep -c '^Band ')" = 2 ] || bad "the input has not two bands"
	run "$TP" "$T/two.tif" --res 1000 -o "$T/two.exr" -v
	expect_rc 0; expect_err "83x113 samples of 1000x1000 m, EPSG:32617, heights 75..456.179 m"
	rm -f "$T"/b1.tif "$T"/b2.tif "$T"/two.*
	end
else
	skip terrainprep_uses_the_first_band_of_many "$DEM/n43.dt0 is absent"
fi

begin terrainprep_formats_crops_and_sizes
if have_dem n43.dt0 ; then
	need_gdal
	n="$DEM/n43.dt0"
	run "$TP" "$n" --size unity -o "$T/u.r16"
	expect_rc 0
	[ "$(wc -c <"$T/u.r16")" -eq $((257 * 257 * 2)) ] || bad "unity r16 is $(wc -c <"$T/u.r16") bytes"
	grep -q '"type":	"uint16le"' "$T/u.json" || bad "r16 type"
	[ "$(json_num "$T/u.json" offset)" = 75 ] || bad "r16 offset"
	run "$TP" "$n" --size unity --flip -f r16 -o "$T/f.raw"; expect_rc 0
	grep -q '"row_order":	"south-up"' "$T/f.json" || bad "flip not recorded"
	run "$TP" "$n" --res 1000 -o "$T/g.tif"; expect_rc 0
	gdalinfo "$T/g.tif" >"$T/info" 2>&1
	grep -q 'Size is 83, 113' "$T/info" || bad "tif size"
	grep -q 'Type=Float32' "$T/info" || bad "tif type"
	grep -q 'ID\["EPSG",32617\]' "$T/info" || bad "tif CRS"
	run "$TP" "$n" --center 43.5,-79.5 --radius 10 --res 500 -o "$T/c.exr"
	expect_rc 0
	[ "$(json_num "$T/c.json" width)" = 40 ] || bad "crop width $(json_num "$T/c.json" width)"
	near "$(sed -n '/"center"/,/}/p' "$T/c.json" | json_num /dev/stdin lat)" 43.5 1e-6 || bad "crop centre"
	run "$TP" "$n" --bounds 600000,4800000,620000,4830000 --size 40 -o "$T/b.exr"
	expect_rc 0
	[ "$(json_num "$T/b.json" width)x$(json_num "$T/b.json" height)" = 27x40 ] ||
		bad "bounds size $(json_num "$T/b.json" width)x$(json_num "$T/b.json" height)"
	run "$TP" "$n" --bounds -79.6,43.4,-79.4,43.6 --bounds-srs EPSG:4326 --res 1000 -o "$T/b.exr" -v
	expect_rc 0; expect_err "16x23 samples of 1000x1000 m, EPSG:32617"
	run "$TP" "$n" --t-srs EPSG:3857 --size 50x60 -r cubic -o "$T/w.exr"; expect_rc 0
	[ "$(json_num "$T/w.json" epsg)" = 3857 ] || bad "--t-srs not used"
	grep -q '"resampling":	"cubic"' "$T/w.json" || bad "-r not used"
	run "$TP" "$n" --center 10,10 --radius 5 -o "$T/out.exr"
	expect_rc 1; expect_err "no heights in the output grid"
	run "$TP" "$n" --t-srs EPSG:4326 -o "$T/geo.exr"
	expect_rc 2; expect_err "not a projected CRS in metres"
	run "$TP" "$n" --res 0.01 -o "$T/huge.exr"
	expect_rc 2; expect_err "samples (at most"
	rm -f "$T"/*
	end
else
	skip terrainprep_formats_crops_and_sizes "$DEM/n43.dt0 is absent"
fi

begin terrainprep_hillshade_png
if have_dem n43.dt0; then
	run "$TP" "$DEM/n43.dt0" --hillshade "$T/h.png" --azimuth 90 --altitude 30 --z-factor 5
	expect_rc 0; expect_file "$T/h.png"; expect_no_file "$T/h.json"
	dims=$(od -An -tu1 -j16 -N8 "$T/h.png" | tr -s ' ')
	[ "$dims" = " 0 0 0 103 0 0 0 140" ] || bad "hillshade size bytes '$dims'"
	rm -f "$T/h.png"
	end
else
	skip terrainprep_hillshade_png "$DEM/n43.dt0 is absent"
fi

begin terrainprep_reports_bad_input
printf 'not a DEM\n' >"$T/text.dem"
run "$TP" "$T/text.dem" -o "$T/o.exr"
expect_rc 1; expect_err "terrainprep: \`$T/text.dem' not recognized as a supported file format"
run "$TP" "$T/nope.tif" -o "$T/o.exr"
expect_rc 1; expect_err "terrainprep: $T/nope.tif: No such file or directory"
expect_no_file "$T/o.exr"; expect_no_file "$T/o.json"
rm -f "$T"/*
end

begin terrainprep_reports_a_truncated_dem
if have_dem n43.dt0; then
	head -c 20000 "$DEM/n43.dt0" >"$T/trunc.dt0"
	run "$TP" "$T/trunc.dt0" -o "$T/o.exr"
	expect_rc 1; expect_err "trunc.dt0 is damaged: Failed to seek to, or read profile"
	expect_no_file "$T/o.exr"; expect_no_file "$T/o.json"
	rm -f "$T"/*
	end
else
	skip terrainprep_reports_a_truncated_dem "$DEM/n43.dt0 is absent"
fi

begin terrainprep_unwritable_output_leaves_nothing
if have_dem nodata_float.asc; then
	a="$DEM/nodata_float.asc"
	mkdir "$T/ro"; echo keep >"$T/ro/t.exr"; chmod 555 "$T/ro"
	if [ -w "$T/ro" ]; then
		run "$TP" "$a" --s-srs EPSG:32611 -o "$T/missing/t.exr"
		expect_rc 1; expect_err "terrainprep: cannot create $T/missing/t.json"
		expect_no_file "$T/missing"
	else
		run "$TP" "$a" --s-srs EPSG:32611 -o "$T/ro/t.exr"
		expect_rc 1; expect_err "terrainprep: cannot create"
		[ "$(cat "$T/ro/t.exr")" = keep ] || bad "existing file clobbered"
		expect_only_files "$T/ro" 1
	fi
	chmod 755 "$T/ro"
	# the sidecar's place is taken by a folder: no data file either
	mkdir "$T/ro/u.json"
	run "$TP" "$a" --s-srs EPSG:32611 -o "$T/ro/u.exr"
	expect_rc 1; expect_err "Is a directory"; expect_no_file "$T/ro/u.exr"
	rm -rf "$T/ro"
	end
else
	skip terrainprep_unwritable_output_leaves_nothing "$DEM/nodata_float.asc is absent"
fi

begin terrainprep_bad_options_are_usage_errors
for args in "" "-o x.exr" "in.tif" "-o - in.tif" "-o x.json in.tif" "--format png -o x in.tif" \
	"--res 0 -o x.exr in.tif" "--res abc -o x.exr in.tif" "--res 10 --size 100 -o x.exr in.tif" \
	"--size 1 -o x.exr in.tif" "--size 10x -o x.exr in.tif" "--size x10 -o x.exr in.tif" \
	"--size huge -o x.exr in.tif" "--center 46.9 --radius 5 -o x.exr in.tif" \
	"--center 95,7 --radius 5 -o x.exr in.tif" "--center 1,2,3 --radius 5 -o x.exr in.tif" \
	"--center 46.9,7 -o x.exr in.tif" "--radius 5 -o x.exr in.tif" \
	"--radius 0 --center 1,1 -o x.exr in.tif" "--center 1,1 --radius 1 --bounds 0,0,1,1 -o x.exr in.tif" \
	"--bounds 0,0,1 -o x.exr in.tif" "--bounds 0,0,1,1,1 -o x.exr in.tif" \
	"--bounds 1,0,0,1 -o x.exr in.tif" "--bounds-srs EPSG:4326 -o x.exr in.tif" \
	"-r fancy -o x.exr in.tif" "--fill zero -o x.exr in.tif" "--fill value=abc -o x.exr in.tif" \
	"--max-void-fraction 1.5 -o x.exr in.tif" "--flip -o x.exr in.tif" \
	"--fill none -o x.r16 in.tif" "--azimuth 400 -o x.exr in.tif" "--altitude -1 -o x.exr in.tif" \
	"--z-factor 0 -o x.exr in.tif" "--scale 0 -o x.exr in.tif" "--stdin-name a/b -o x.exr -" \
	"--src-nodata abc -o x.exr in.tif" "--bogus" "- - -o x.exr" "--t-srs nonsense -o x.exr in.tif"; do
	# shellcheck disable=SC2086
	(cd "$T" && "$TP" $args >"$T/out" 2>"$T/err" </dev/null); rc=$?
	[ "$rc" -eq 2 ] || bad "'$args' exited $rc, expected 2"
	grep -q '^terrainprep: \|^Try ' "$T/err" || bad "'$args' gave no 'terrainprep:' message"
done
[ ! -e "$T/x.exr" ] || bad "a usage error left x.exr"
end

begin terrainprep_help_version_and_man_page
run "$TP" --help; expect_rc 0; expect_out "Usage: terrainprep"
for o in --output --format --stdin-name --s-srs --t-srs --center --radius --bounds \
	--bounds-srs --res --size --resampling --src-nodata --fill --max-void-fraction \
	--flip --hillshade --azimuth --altitude --z-factor --scale --quiet --verbose \
	--help --version; do
	grep -q -- "$o" "$T/out" || bad "--help lacks $o"
	grep -q -- "Fl ${o#-}" "$TOP/man/terrainprep.1" || bad "man page lacks $o"
done
run "$TP" --version; expect_rc 0; expect_out "terrainprep (cloudscape)"
end

begin make_bern_dem_is_synthetic_with_true_summits
{
	need_gdal
	run "$TOP/scripts/make-bern-dem" -r 100 "$T/bern-synthetic.tif"
	expect_rc 0; expect_file "$T/bern-synthetic.tif"
	gdalinfo "$T/bern-synthetic.tif" >"$T/info"
	grep -q 'SYNTHETIC=YES' "$T/info" || bad "not labelled SYNTHETIC"
	grep -q 'DESCRIPTION=SYNTHETIC elevation model' "$T/info" || bad "no description"
	grep -q 'ID\["EPSG",2056\]' "$T/info" || bad "not EPSG:2056"
	grep -q 'Size is 200, 200' "$T/info" || bad "not 20 km at 100 m"
	h() { gdallocationinfo -valonly -wgs84 "$T/bern-synthetic.tif" "$1" "$2"; }
	near "$(h 7.44361 46.91722)" 858 3 || bad "Gurten at $(h 7.44361 46.91722) m"
	near "$(h 7.52916 46.97917)" 947 3 || bad "Bantiger at $(h 7.52916 46.97917) m"
	# the Aare below the Bern old town (Marzili), LV95 2600800/1199100
	near "$(gdallocationinfo -valonly -geoloc "$T/bern-synthetic.tif" 2600800 1199100)" 540 10 ||
		bad "Aare valley floor"
	run "$TP" "$T/bern-synthetic.tif" -o "$T/bern.exr" -v
	expect_rc 0; expect_err "200x200 samples of 100x100 m, EPSG:2056"
	run "$TOP/scripts/make-bern-dem" -r 7 "$T/x.tif"; expect_rc 2
	end
}
