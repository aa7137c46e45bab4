# Output formats and the conventions of every output, as a user meets them:
# each format read back by an outside tool (GDAL, netpbm, OpenEXR's
# exrheader) with its pixel values checked; all-or-nothing multi-output
# runs; --no-clobber; the same output twice.
. "$TOP/tests/tools/lib.sh"
plan 7
CR="$BIN/cloudrender"
NB="$BIN/noisebake"
TP="$BIN/terrainprep"
WI="$BIN/wxinterp"
FAST="--size 48x27 --quality low --noise-size 16 -q"
have() { command -v "$1" >/dev/null 2>&1; }
# px FILE X Y: the band values of one pixel, as GDAL reads them
px() { gdallocationinfo -valonly "$1" "$2" "$3" | tr '\n' ' '; }
# band_type FILE N: GDAL's data type of band N
band_type() { gdalinfo "$1" | sed -n "s/^Band $2 .*Type=\([A-Za-z0-9]*\).*/\1/p"; }
# within A B TOL: |A - B| <= TOL
within() { awk -v a="$1" -v b="$2" -v t="$3" 'BEGIN { d = a - b; exit !(a != "" && b != "" && (d < 0 ? -d : d) <= t) }'; }
# display8 L: the 8-bit PNG value of linear radiance L (kcd/m^2) at
# exposure 0, from the published curves: x = L / 16, Narkowicz's ACES fit
# x(2.51x + 0.03) / (x(2.43x + 0.59) + 0.14), IEC 61966-2-1's sRGB encoding
display8() {
	awk -v l="$1" 'BEGIN { x = l / 16; if (x < 0) x = 0
		y = x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14)
		if (y > 1) y = 1; if (y < 0) y = 0
		v = y <= 0.0031308 ? 12.92 * y : 1.055 * exp(log(y) / 2.4) - 0.055
		printf "%d", int(255 * v + 0.5) }'
}
# dem FILE: a small 24x20 DEM (UTM 32N, 100 m pixels, a slope), as GeoTIFF
dem() {
	{ printf 'ncols 24\nnrows 20\nxllcorner 380000\nyllcorner 5200000\ncellsize 100\n'
	  awk 'BEGIN { for (r = 0; r < 20; r++) { s = ""; for (c = 0; c < 24; c++) s = s " " (500 + 10 * c + 5 * r); print s } }'
	} >"$T/dem.asc"
	gdal_translate -q -a_srs EPSG:32632 "$T/dem.asc" "$1" && rm -f "$T/dem.asc"
}

begin cloudrender_formats_read_back_by_gdal_netpbm_and_exrheader
if have gdallocationinfo && have pngtopnm && have exrheader; then
	run "$CR" $FAST -o "$T/a.png" -o "$T/b.tif" -o "$T/c.jpg" -o "$T/d.exr"
	expect_rc 0
	run "$CR" $FAST --png16 --float -o "$T/p16.png" -o "$T/f.tif" -o "$T/f.exr"
	expect_rc 0
	gdalinfo "$T/a.png" | grep -q '^Driver: PNG/' || bad "a.png is not a PNG to GDAL"
	gdalinfo "$T/b.tif" | grep -q '^Driver: GTiff/' || bad "b.tif is not a TIFF to GDAL"
	gdalinfo "$T/c.jpg" | grep -q '^Driver: JPEG/' || bad "c.jpg is not a JPEG to GDAL"
	[ "$(band_type "$T/a.png" 1)" = Byte ] || bad "a.png band 1 is $(band_type "$T/a.png" 1)"
	[ "$(band_type "$T/p16.png" 3)" = UInt16 ] || bad "--png16 band 3 is $(band_type "$T/p16.png" 3)"
	[ "$(band_type "$T/b.tif" 3)" = UInt16 ] || bad "b.tif band 3 is $(band_type "$T/b.tif" 3)"
	[ "$(band_type "$T/f.tif" 5)" = Float32 ] || bad "--float TIFF band 5 is $(band_type "$T/f.tif" 5)"
	gdalinfo "$T/f.tif" | grep -q 'Description = Z' || bad "--float TIFF has no Z band"
	[ "$(pngtopnm "$T/p16.png" | sed -n 3p)" = 65535 ] || bad "pngtopnm: --png16 is not 16-bit"
	exrheader "$T/d.exr" | grep -q 'R, 16-bit floating-point' || bad "d.exr R is not half"
	exrheader "$T/d.exr" | grep -q 'Z, 32-bit floating-point' || bad "d.exr Z is not float"
	exrheader "$T/f.exr" | grep -q 'R, 32-bit floating-point' || bad "--float EXR R is not float"
	exrheader "$T/f.exr" | grep -q 'A, 32-bit floating-point' || bad "--float EXR A is not float"
	for xy in "3 2" "24 5" "40 20" "10 25"; do
		set -- $xy
		a=$(px "$T/a.png" "$1" "$2"); p=$(px "$T/p16.png" "$1" "$2")
		t=$(px "$T/b.tif" "$1" "$2"); f=$(px "$T/f.tif" "$1" "$2")
		[ "$p" = "$t" ] || bad "($xy): 16-bit PNG $p and 16-bit TIFF $t differ"
		for c in 1 2 3; do
			a8=$(echo "$a" | cut -d' ' -f$c); p16=$(echo "$p" | cut -d' ' -f$c)
			lin=$(echo "$f" | cut -d' ' -f$c)
			within "$(awk -v v="$p16" 'BEGIN { print v / 257 }')" "$a8" 0.51 ||
				bad "($xy) band $c: 16-bit $p16 is not 257 x the 8-bit $a8"
			within "$(display8 "$lin")" "$a8" 1 ||
				bad "($xy) band $c: the float TIFF's $lin kcd/m2 displays as $(display8 "$lin"), the PNG holds $a8"
		done
		alpha=$(echo "$f" | cut -d' ' -f4)
		within "$alpha" 0.5 0.5 || bad "($xy): alpha $alpha outside 0..1"
	done
	# JPEG is lossy: its band means agree with the PNG's
	for c in 1 2 3; do
		mp=$(gdalinfo -stats "$T/a.png" | sed -n 's/.*STATISTICS_MEAN=//p' | sed -n ${c}p)
		mj=$(gdalinfo -stats "$T/c.jpg" | sed -n 's/.*STATISTICS_MEAN=//p' | sed -n ${c}p)
		within "$mj" "$mp" 3 || bad "band $c mean: JPEG $mj, PNG $mp"
	done
	end
else
	skip cloudrender_formats_read_back_by_gdal_netpbm_and_exrheader "gdal-bin, netpbm or openexr is missing"
fi

begin cloudrender_jpeg_quality_and_of_choose_what_is_written
if have gdalinfo; then
	run "$CR" $FAST --jpeg-quality 10 -o "$T/q10.jpg"; expect_rc 0
	run "$CR" $FAST --jpeg-quality 98 -o "$T/q98.jpg"; expect_rc 0
	[ "$(wc -c <"$T/q10.jpg")" -lt "$(wc -c <"$T/q98.jpg")" ] ||
		bad "quality 10 is not smaller than quality 98"
	run "$CR" $FAST -of GTiff -o "$T/frame.dat" -of jpeg -o "$T/frame.png"
	expect_rc 0
	gdalinfo "$T/frame.dat" | grep -q '^Driver: GTiff/' || bad "-of GTiff did not write a TIFF"
	gdalinfo "$T/frame.png" | grep -q '^Driver: JPEG/' || bad "-of jpeg did not write a JPEG"
	run "$CR" $FAST -of TIFF -o - ; expect_rc 0
	head -c 4 "$T/out" | od -An -tx1 | grep -q '49 49 2a 00' || bad "-of TIFF -o - is not a TIFF"
	run "$CR" $FAST -o "$T/x.webp"; expect_rc 2
	expect_err "-o $T/x.webp: unknown format: the name must end in .png, .exr, .tif, .tiff, .jpg or .jpeg"
	run "$CR" $FAST -of BMP -o "$T/x.bmp"; expect_rc 2
	expect_err "-of: unknown format 'BMP': use PNG, EXR, GTiff (or TIFF) or JPEG (or JPG)"
	run "$CR" $FAST -o "$T/y.png" -of PNG; expect_rc 2; expect_err "-of applies to the -o outputs after it"
	run "$CR" $FAST --jpeg-quality 0 -o "$T/y.jpg"; expect_rc 2; expect_err "--jpeg-quality: 0 is out of range 1..100"
	expect_no_file "$T/x.webp"; expect_no_file "$T/x.bmp"; expect_no_file "$T/y.png"; expect_no_file "$T/y.jpg"
	end
else
	skip cloudrender_jpeg_quality_and_of_choose_what_is_written "gdal-bin is missing"
fi

begin the_same_output_twice_is_a_usage_error
mkdir "$T/twice" && cd "$T/twice" || exit 1
run "$CR" $FAST -o a.png -o a.png; expect_rc 2; expect_err "a.png is named twice as an output"
run "$CR" $FAST -o a.png -o ./a.png; expect_rc 2; expect_err "named twice"
run "$CR" $FAST -o - -o -; expect_rc 2
run "$NB" -s 16 -q -o n.exr -o m.exr; expect_rc 2; expect_err "-o: one output only (given twice)"
run "$WI" -o a.json -o b.json; expect_rc 2; expect_err "-o: one output only"
run "$TP" -o t.exr -o u.exr x.tif; expect_rc 2; expect_err "-o: one output only"
run "$TP" -o t.png --hillshade t.png x.tif; expect_rc 2
cd "$T" || exit 1
expect_only_files "$T/twice" 0
end

begin multi_output_runs_leave_nothing_when_one_output_fails
mkdir "$T/aon" "$T/aon/dir.exr" "$T/aon/dir.png"
run "$CR" $FAST -o "$T/aon/a.png" -o "$T/aon/b.tif" -o "$T/aon/dir.exr"
expect_rc 1; expect_err "cannot write $T/aon/dir.exr: Is a directory"
run "$NB" -s 16 -q -o "$T/aon/n.exr" --preview "$T/aon/dir.png"
expect_rc 1; expect_err "dir.png: Is a directory"
if have gdal_translate && dem "$T/dem.tif"; then
	run "$TP" -q "$T/dem.tif" -o "$T/aon/out.exr" --hillshade "$T/aon/dir.png"
	expect_rc 1; expect_err "dir.png: Is a directory"
	# a good run writes all three
	run "$TP" -q "$T/dem.tif" -o "$T/good.exr" --hillshade "$T/good.png"
	expect_rc 0; expect_file "$T/good.exr"; expect_file "$T/good.json"; expect_file "$T/good.png"
else
	bad "cannot make a test DEM with gdal_translate"
fi
expect_only_files "$T/aon" 2
end

begin outputs_are_checked_before_the_inputs_are_read
# an unwritable output is found before the work: before even opening the
# (missing) inputs
run "$CR" $FAST --wx "$T/none.json" -o "$T/nodir/a.png"
expect_rc 1; expect_err "cannot create $T/nodir/a.png"
run "$TP" "$T/none.tif" -o "$T/nodir/t.exr"
expect_rc 1; expect_err "cannot create $T/nodir/t"
run "$WI" --at 2024-10-07T12:00Z "$T/none.json" -o "$T/nodir/w.json"
expect_rc 1; expect_err "cannot create $T/nodir/w.json"
end

begin terrainprep_refuses_a_heightfield_named_as_an_image
run "$TP" -o "$T/t.png" "$T/none.tif"
expect_rc 2; expect_err "-o $T/t.png: a heightfield is EXR, GeoTIFF or 16-bit raw: name it .exr, .tif, .tiff, .r16 or .raw"
run "$TP" --hillshade "$T/h.jpg" "$T/none.tif"
expect_rc 2; expect_err "the hillshade is a PNG"
expect_no_file "$T/t.png"; expect_no_file "$T/t.json"; expect_no_file "$T/h.jpg"
end

begin no_clobber_refuses_to_replace_for_every_program
mkdir "$T/nc" && cd "$T/nc" || exit 1
for f in a.png n.exr p.png w.json t.exr; do echo old >"$f"; done
unchanged() { for f in a.png n.exr p.png w.json t.exr; do
	[ "$(cat "$f")" = old ] || bad "$1 replaced $f"; done; }
run "$CR" $FAST --no-clobber -o new.tif -o a.png
expect_rc 1; expect_err "a.png exists: not overwritten (--no-clobber)"; expect_no_file new.tif
unchanged cloudrender
run "$NB" -s 16 -q --no-clobber -o new.exr --preview p.png
expect_rc 1; expect_err "p.png exists"; expect_no_file new.exr; unchanged noisebake
run "$WI" --template --no-clobber -o w.json
expect_rc 1; expect_err "w.json exists"; unchanged wxinterp
run "$TP" --no-clobber -o t.exr "$T/none.tif"
expect_rc 1; expect_err "t.exr exists"; unchanged terrainprep
run "$BIN/mbfetch" --no-clobber --provider open-meteo --site bern -o w.json
expect_rc 1; expect_err "w.json exists"; unchanged mbfetch
# new files are written; without the option old ones are replaced
run "$CR" $FAST --no-clobber -o new.png; expect_rc 0; expect_file new.png
run "$WI" --template --no-clobber -o /dev/null; expect_rc 0
run "$WI" --template -o w.json; expect_rc 0
grep -q cloudwx w.json || bad "without --no-clobber w.json was not replaced"
for p in cloudrender noisebake terrainprep wxinterp mbfetch; do
	"$BIN/$p" --help | grep -q -- '--no-clobber' || bad "$p --help lacks --no-clobber"
	grep -q 'Fl -no-clobber' "$TOP/man/$p.1" || bad "$p(1) lacks --no-clobber"
done
cd "$T" || exit 1
end
