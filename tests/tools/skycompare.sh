# skycompare as a user runs it.  Expected values come from closed forms
# computed here in awk (IEC 61966-2-1's sRGB decoding written again), never
# from skycompare itself.
. "$TOP/tests/tools/lib.sh"
plan 12
SC="$BIN/skycompare"
CR="$BIN/cloudrender"
WX="$BIN/wxinterp"
FAST="--size 48x27 --quality low --noise-size 16 -q"

# pixels FILE.png: "W H" then one "R G B" line per pixel, rows top down
pixels() {
	pngtopnm "$1" | pnmtoplainpnm | awk 'NR == 2 { print $1, $2; next } NR <= 3 { next }
		{ for (i = 1; i <= NF; i++) { v[n++ % 3] = $i; if (n % 3 == 0) print v[0], v[1], v[2] } }'
}
# topng OUT.png: a "W H" line and "R G B" lines on stdin to a PNG
topng() {
	awk 'NR == 1 { print "P3"; print $1, $2; print 255; next } { print }' | pnmtopng >"$1"
}
# json NAME: the first number after "NAME": in $T/out
json() { grep -o "\"$1\":[-0-9.e]*" "$T/out" | head -1 | cut -d: -f2; }
# near A B TOL: |A - B| <= TOL
near() { awk -v a="$1" -v b="$2" -v t="$3" 'BEGIN { d = a - b; exit !(a != "" && (d < 0 ? -d : d) <= t) }'; }
AWK_SRGB='function lin(v) { v /= 255; return v <= 0.04045 ? v / 12.92 : ((v + 0.055) / 1.055) ^ 2.4 }
function enc(x) { x = x <= 0.0031308 ? 12.92 * x : 1.055 * x ^ (1 / 2.4) - 0.055; x = int(255 * x + 0.5); return x > 255 ? 255 : x < 0 ? 0 : x }
function Y(r, g, b) { return 0.2126 * lin(r) + 0.7152 * lin(g) + 0.0722 * lin(b) }'

"$CR" -o "$T/r.png" -o "$T/r.exr" $FAST || echo "FAIL skycompare: cloudrender could not make the test render"

begin skycompare_identical_pictures_give_zero_distances
run "$SC" "$T/r.png" "$T/r.png" --json
expect_rc 0
expect_out '"emd_levels":{"r":0.0000,"g":0.0000,"b":0.0000,"mean":0.0000}'
expect_out '"chi2":{"r":0.00000,"g":0.00000,"b":0.00000,"mean":0.00000}'
expect_out '"cloud_fraction":0.0000,"cloud_disagreement":0.0000'
expect_out '"mean_abs_level":0.000'
expect_out '"verdict":"match"'
# the EXR through cloudrender's display transform is its PNG, but for the
# EXR's half floats: a level here and there, 0.005 on average measured
run "$SC" "$T/r.exr" "$T/r.png" --json
expect_rc 0
near "$(json mean_abs_level)" 0 0.02 || bad "EXR and PNG differ by $(json mean_abs_level) levels"
expect_out '"method":"depth"'
run "$SC" "$T/r.png" "$T/r.png"
expect_out 'verdict: match: the same cloud cover'
end

begin skycompare_shifted_picture_keeps_its_histograms_and_moves_its_pixels
# a grey ramp, level x in column x, against itself moved 16 columns (with
# wrap-around): the same histograms, and a mean |difference| of
# (240 x 16 + 16 x 240) / 256 = 30 levels
awk 'BEGIN { print 256, 4; for (y = 0; y < 4; y++) for (x = 0; x < 256; x++) print x, x, x }' |
	topng "$T/ramp.png"
awk 'BEGIN { print 256, 4; for (y = 0; y < 4; y++) for (x = 0; x < 256; x++) { v = (x + 240) % 256; print v, v, v } }' |
	topng "$T/ramp16.png"
run "$SC" --sky-all "$T/ramp.png" "$T/ramp16.png" --json
expect_rc 0
expect_out '"emd_levels":{"r":0.0000,"g":0.0000,"b":0.0000,"mean":0.0000}'
expect_out '"mean_abs_level":30.000'
expect_out '"mean_level":[0.000,0.000,0.000]'
# the render moved 5 columns: histograms, cloud fraction and luminance stay
pixels "$T/r.png" | awk 'NR == 1 { w = $1; print; next } { row[(NR - 2) % w] = $0 }
	(NR - 1) % w == 0 { for (x = 0; x < w; x++) print row[(x + w - 5) % w] }' | topng "$T/r5.png"
run "$SC" --sky-all "$T/r.png" "$T/r5.png" --json
expect_rc 0
expect_out '"emd_levels":{"r":0.0000,"g":0.0000,"b":0.0000,"mean":0.0000}'
expect_out '"cloud_fraction":0.0000,"cloud_disagreement"'
[ "$(json luminance_ratio)" = "1.00000" ] || bad "luminance ratio $(json luminance_ratio), expected 1"
near "$(json mean_abs_level)" 0 0.5 && bad "moved pixels show no difference"
end

begin skycompare_exposure_change_scales_luminance_by_two_to_the_ev
# the render one stop darker (linear values halved, re-encoded): the
# render's mean luminance over the darker one's is awk's ratio of the two
# pictures' (about 2), the red/blue ratios and so the cloud fraction hardly move
pixels "$T/r.png" | awk "$AWK_SRGB"'NR == 1 { print; next } { print enc(lin($1) / 2), enc(lin($2) / 2), enc(lin($3) / 2) }' |
	topng "$T/dark.png"
want=$( { pixels "$T/r.png"; pixels "$T/dark.png"; } | awk "$AWK_SRGB"'
	NF == 2 { f++; next } { s[f] += Y($1, $2, $3) } END { printf "%.5f", s[1] / s[2] }')
run "$SC" --sky-all "$T/r.png" "$T/dark.png" --json
expect_rc 0
near "$(json luminance_ratio)" "$want" 0.0001 || bad "luminance ratio $(json luminance_ratio), awk's $want"
near "$want" 2 0.04 || bad "awk's ratio $want is not about 2"
d=$(grep -o '"difference":{[^}]*' "$T/out" | grep -o '"cloud_fraction":[-0-9.]*' | cut -d: -f2)
near "$d" 0 0.03 || bad "cloud fraction moved by $d"
run "$SC" --sky-all "$T/r.png" "$T/dark.png"
expect_out '% brighter'
run "$SC" --sky-all "$T/dark.png" "$T/r.png"
expect_out '% darker'
end

begin skycompare_cloud_fraction_of_known_pixels_is_exact
# random colours; awk classifies each by R/B on decoded sRGB
awk 'BEGIN { srand(14); print 50, 20; for (i = 0; i < 1000; i++) print int(256 * rand()), int(256 * rand()), 1 + int(255 * rand()) }' >"$T/rand.txt"
topng "$T/rand.png" <"$T/rand.txt"
for thr in 0.75 0.5 1.2; do
	want=$(awk "$AWK_SRGB"' NR > 1 { n += lin($1) / lin($3) >= '"$thr"' } END { print n }' "$T/rand.txt")
	run "$SC" --sky-all --threshold "$thr" "$T/rand.png" "$T/rand.png" --json
	expect_rc 0
	[ "$(json cloud_pixels)" = "$want" ] || bad "threshold $thr: $(json cloud_pixels) cloud pixels, awk counts $want"
done
# 237 grey cloud pixels in 800 of blue sky: 0.2963
awk 'BEGIN { print 40, 20; for (i = 0; i < 800; i++) print (i < 237 ? "200 200 205" : "80 130 215") }' |
	topng "$T/cf.png"
run "$SC" --sky-all "$T/cf.png" "$T/cf.png"
expect_rc 0
expect_out 'cloud fraction      0.296 '
# through GDAL: a GeoTIFF (lossless) and a JPEG
gdal_translate -q -of GTiff "$T/rand.png" "$T/rand.tif" || bad "gdal_translate failed"
want=$(awk "$AWK_SRGB"' NR > 1 { n += lin($1) / lin($3) >= 0.75 } END { print n }' "$T/rand.txt")
run "$SC" --sky-all "$T/rand.png" "$T/rand.tif" --json
expect_rc 0
expect_out '"mean_abs_level":0.000'
cp "$T/out" "$T/tif.json"
[ "$(grep -o '"photo":{.*' "$T/tif.json" | grep -o '"cloud_pixels":[0-9]*' | head -1)" = "\"cloud_pixels\":$want" ] ||
	bad "the GeoTIFF's cloud pixels differ from awk's $want"
# JPEG's chroma subsampling blurs colour edges: cloud in whole 8 x 8
# blocks, a quarter of the picture; the tolerance: the edge band (48 of
# 2048 pixels a pixel wide, 0.023), which turns bluer
awk 'BEGIN { print 64, 32; for (y = 0; y < 32; y++) for (x = 0; x < 64; x++)
	print (x < 32 && y < 16 ? "200 200 205" : "80 130 215") }' | topng "$T/q.png"
gdal_translate -q -of JPEG -expand rgb -co QUALITY=100 "$T/q.png" "$T/q.jpg" || bad "gdal_translate failed"
run "$SC" --sky-all "$T/q.png" "$T/q.jpg" --json
expect_rc 0
expect_out '"size":[64,32]'
pc=$(grep -o '"photo":{.*' "$T/out" | grep -o '"cloud_fraction":[0-9.]*' | head -1 | cut -d: -f2)
near "$pc" 0.25 0.03 || bad "the JPEG's cloud fraction $pc, expected 0.25 within JPEG's loss"
end

begin skycompare_cloud_fraction_rises_with_coverage_for_every_genus
# toward the sun's side (the template's sun: azimuth 245, elevation 52), 30
# degrees up, as a sky imager sees it: a thin veil of cirrostratus shows by
# the light it scatters forward and is all but invisible away from the sun
for g in cumulus stratocumulus stratus nimbostratus cumulonimbus altocumulus altostratus \
	cirrus cirrocumulus cirrostratus; do
	prev=-1
	first=""
	for c in 0.15 0.5 0.9; do
		"$WX" --template --set 'layers[1]=none' --set "layers[0]=$g" \
			--set "layers[0].coverage=$c" >"$T/g.json" 2>"$T/err" &&
			"$CR" --wx "$T/g.json" -o "$T/g.exr" $FAST --look 245,30 2>"$T/err" ||
			{ bad "$g $c: could not render: $(head -c 200 "$T/err")"; continue; }
		run "$SC" "$T/g.exr" "$T/g.exr" --json
		f=$(json cloud_fraction)
		first=${first:-$f}
		# rising, or already all cloud
		awk -v p="$prev" -v f="$f" 'BEGIN { exit !(f > p || (f >= 0.99 && p >= 0.99)) }' ||
			bad "$g: cloud fraction $f at coverage $c, after $prev"
		prev=$f
	done
	awk -v a="$first" -v b="$prev" 'BEGIN { exit !(b - a >= 0.1) }' ||
		bad "$g: cloud fraction from $first to only $prev over coverage 0.15..0.9"
done
# a clear sky is clear above the haze of the horizon (the lowest 4 of its
# 18 rows of sky); with the haze it is not
"$WX" --template --set 'layers[1]=none' --set 'layers[0]=none' >"$T/c.json" &&
	"$CR" --wx "$T/c.json" -o "$T/c.exr" $FAST || bad "no clear render"
run "$SC" "$T/c.exr" "$T/c.exr" --render-horizon 14 --horizon 14 --json
expect_out '"method":"depth+horizon"'
near "$(json cloud_fraction)" 0 0.03 || bad "clear sky: cloud fraction $(json cloud_fraction)"
run "$SC" "$T/c.exr" "$T/c.exr" --json
near "$(json cloud_fraction)" 0 0.1 && bad "the haze band is not cloud any more: $(json cloud_fraction)"
end

begin skycompare_undo_tonemap_classifies_a_render_png_like_its_exr
# cloudrender's display transform pales the sky: its PNG's decoded R/B is
# well above its EXR's; inverting ACES and the exposure brings it back
run "$SC" "$T/r.png" "$T/r.exr" --json
d=$(grep -o '"difference":{[^}]*' "$T/out" | grep -o '"cloud_fraction":[-0-9.]*' | cut -d: -f2)
near "$d" 0 0.1 && bad "the PNG classifies like the EXR without --undo-tonemap ($d)"
run "$SC" "$T/r.png" "$T/r.exr" --undo-tonemap --json
expect_rc 0
d=$(grep -o '"difference":{[^}]*' "$T/out" | grep -o '"cloud_fraction":[-0-9.]*' | cut -d: -f2)
near "$d" 0 0.02 || bad "with --undo-tonemap the PNG's cloud fraction is $d off its EXR's"
expect_out '"mean_luminance_kcd_m2"'
end

begin skycompare_sky_masks_from_depth_mask_horizon_and_estimate
run "$SC" "$T/r.exr" "$T/r.png" --json
expect_rc 0
fr=$(grep -o '"render":{.*' "$T/out" | grep -o '"fraction":[0-9.]*' | head -1 | cut -d: -f2)
fp=$(grep -o '"photo":{.*' "$T/out" | grep -o '"fraction":[0-9.]*' | head -1 | cut -d: -f2)
near "$fr" 0.6 0.3 || bad "the render's depth mask holds $fr of the picture"
near "$fp" "$fr" 0.04 || bad "the estimate ($fp) is far from the depth mask ($fr) at a flat horizon"
expect_out '"method":"auto"'
run "$SC" "$T/cf.png" "$T/cf.png" --horizon 5 --json
expect_rc 0
[ "$(grep -o '"photo":{.*' "$T/out" | grep -o '"pixels":[0-9]*' | head -1)" = '"pixels":200' ] ||
	bad "--horizon 5 of a 40-wide photo is not 200 sky pixels"
awk 'BEGIN { print 40, 20; for (i = 0; i < 800; i++) print (i < 280 ? "255 255 255" : "0 0 0") }' |
	topng "$T/mask.png"
run "$SC" "$T/cf.png" "$T/cf.png" --mask "$T/mask.png" --json
expect_rc 0
expect_out '"method":"mask","pixels":280'
run "$SC" "$T/cf.png" "$T/r.png" --mask "$T/mask.png"
expect_rc 1; expect_err "mask.png: the mask is 40x20, its picture 48x27"
end

begin skycompare_crop_fov_and_size_bring_a_photo_onto_the_render
# the render in the middle of a black panorama three times as wide
pngtopnm "$T/r.png" | pnmpad -black -left 48 -right 48 | pnmtopng >"$T/pano.png"
run "$SC" --sky-all "$T/r.png" "$T/pano.png" --crop 48,0,48,27 --json
expect_rc 0; expect_out '"mean_abs_level":0.000'
# perspective: tan(30 deg) / tan(60 deg) = 1/3 of the width
run "$SC" --sky-all "$T/r.png" "$T/pano.png" --fov 60,120 --json
expect_rc 0; expect_out '"mean_abs_level":0.000'
# a panorama: 120 of 360 degrees
run "$SC" --sky-all "$T/r.png" "$T/pano.png" --fov 120,360 --json
expect_rc 0; expect_out '"mean_abs_level":0.000'
run "$SC" --sky-all "$T/r.png" "$T/pano.png"
expect_rc 0; expect_err "warning:"; expect_err "stretched"
# three times larger: area averaging brings it back exactly
pngtopnm "$T/r.png" | pamenlarge 3 | pnmtopng >"$T/big.png"
run "$SC" --sky-all "$T/r.png" "$T/big.png" --json
expect_rc 0; expect_out '"grid":[48,27]'; expect_out '"mean_abs_level":0.000'
run "$SC" --sky-all "$T/big.png" "$T/r.png" --json
expect_rc 0; expect_out '"grid":[144,81]'; expect_out '"emd_levels":{"r":0.0000'
run "$SC" "$T/r.png" "$T/pano.png" --crop 100,0,48,27
expect_rc 2; expect_err "pano.png"; expect_err "not inside the 144x27 picture"
run "$SC" "$T/r.png" "$T/pano.png" --fov 130,120
expect_rc 2; expect_err "wider than the photo"
end

begin skycompare_pictures_side_by_side_overlay_and_difference
awk 'BEGIN { print 40, 20; for (i = 0; i < 800; i++) print "200 60 60" }' | topng "$T/red.png"
awk 'BEGIN { print 40, 20; for (i = 0; i < 800; i++) print "40 60 200" }' | topng "$T/blue.png"
run "$SC" --sky-all "$T/red.png" "$T/blue.png" -o "$T/side.png" --overlay "$T/ov.png" --split 0.25 \
	--diff "$T/diff.png"
expect_rc 0
[ "$(pixels "$T/side.png" | head -1)" = "84 44" ] || bad "side by side is not 2x40+4 by 2x20+4"
[ "$(pixels "$T/ov.png" | head -1)" = "40 20" ] || bad "overlay is not 40x20"
[ "$(pixels "$T/diff.png" | head -1)" = "40 24" ] || bad "difference is not 40x(20+4)"
# the side by side: render top left, photo top right, cloud maps below
# (red's R/B is high: cloud, white; blue's low: clear, blue)
pixels "$T/side.png" | awk 'NR == 1 { w = $1; next } { i = NR - 2; x = i % w; y = int(i / w) }
	x == 1 && y == 1 && $0 != "200 60 60" { print "render: " $0 }
	x == 60 && y == 1 && $0 != "40 60 200" { print "photo: " $0 }
	x == 1 && y == 30 && $0 != "240 240 240" { print "render cloud map: " $0 }
	x == 60 && y == 30 && $0 != "60 120 215" { print "photo cloud map: " $0 }' >"$T/bad"
[ -s "$T/bad" ] && bad "side by side: $(cat "$T/bad")"
# split at 10 of 40 columns: the render left, the photo right; a blend is the mean
pixels "$T/ov.png" | awk 'NR == 1 { w = $1; next } { i = NR - 2; x = i % w; y = int(i / w) }
	x == 2 && y == 1 && $0 != "200 60 60" { print "left: " $0 }
	x == 35 && y == 1 && $0 != "40 60 200" { print "right: " $0 }
	x == 10 && y == 1 && $0 != "250 250 250" { print "divider: " $0 }' >"$T/bad"
[ -s "$T/bad" ] && bad "overlay: $(cat "$T/bad")"
run "$SC" --sky-all "$T/red.png" "$T/blue.png" --overlay "$T/bl.png" --blend 0.5
expect_rc 0
[ "$(pixels "$T/bl.png" | sed -n 2p)" = "120 60 130" ] || bad "blend pixel $(pixels "$T/bl.png" | sed -n 2p)"
# red (Y 0.15) is brighter than blue (Y 0.06): the difference is red
pixels "$T/diff.png" | sed -n 2p | awk '$1 != 255 || $3 >= 255 { exit 1 }' || bad "difference is not red where the render is brighter"
# no temporaries beside the outputs
mkdir "$T/o"
run "$SC" --sky-all "$T/red.png" "$T/blue.png" -o "$T/o/s.png" --diff "$T/o/d.png"
expect_only_files "$T/o" 2
end

begin skycompare_series_reports_each_pair_and_a_summary
mkdir -p "$T/s/r" "$T/s/p" "$T/s/side"
cp "$T/r.png" "$T/s/r/00000.png"; cp "$T/r5.png" "$T/s/r/00001.png"; cp "$T/r.png" "$T/s/r/00002.png"
cp "$T/r.png" "$T/s/p/00000.jpg"; cp "$T/r.png" "$T/s/p/00001.jpg"
run "$SC" --series --sky-all "$T/s/r/%05d.png" "$T/s/p/%05d.jpg" -o "$T/s/side/%05d.png"
expect_rc 0
[ "$(grep -c '^ *[0-9]\{1,\}  ' "$T/out")" -eq 3 ] || bad "not three pair lines: $(cat "$T/out")"
grep -q '^     0  cloud .* +0.000  lum x1.000  EMD   0.0  match' "$T/out" || bad "pair 0 line: $(head -1 "$T/out")"
grep -q '^     2  missing: .*00002.jpg: missing' "$T/out" || bad "no missing line for pair 2"
expect_out 'summary: 3 pairs, 2 compared, 1 missing, 0 failed'
expect_file "$T/s/side/00000.png"; expect_file "$T/s/side/00001.png"; expect_no_file "$T/s/side/00002.png"
run "$SC" --series --sky-all "$T/s/r/%05d.png" "$T/s/p/%05d.jpg" --json --first 1 --last 2
expect_rc 0
[ "$(wc -l <"$T/out")" -eq 3 ] || bad "JSON Lines: not 2 pairs and a summary"
expect_out '"index":1,'; expect_out '"missing":'; expect_out '"summary":{"pairs":2,"compared":1,"missing":1'
echo broken >"$T/s/p/00001.jpg"
run "$SC" --series --sky-all "$T/s/r/%05d.png" "$T/s/p/%05d.jpg"
expect_rc 1
grep -q '^     1  error: .*00001.jpg' "$T/out" || bad "no error line for pair 1"
expect_out '1 failed'; expect_err '1 of 3 pairs could not be compared'
run "$SC" --series "$T/s/r/%05d.png" "$T/s/p/%05d.jpg" --first 7
expect_rc 1; expect_err "no pair of the series could be compared"
end

begin skycompare_bad_inputs_give_clear_errors
run "$SC" "$T/r.png" "$T/absent.jpg"
expect_rc 1; expect_err "skycompare: $T/absent.jpg: cannot open"
echo "not a picture" >"$T/text.png"
run "$SC" "$T/text.png" "$T/r.png"
expect_rc 1; expect_err "skycompare: $T/text.png: not a picture"
head -c 300 "$T/r.png" >"$T/cut.png"
run "$SC" "$T/r.png" "$T/cut.png"
expect_rc 1; expect_err "$T/cut.png"
head -c 400 "$T/r.exr" >"$T/cut.exr"
run "$SC" "$T/cut.exr" "$T/r.png"
expect_rc 1; expect_err "$T/cut.exr"
[ "$(wc -l <"$T/err")" -eq 1 ] || bad "more than one line of error: $(cat "$T/err")"
# an existing output is left alone when the comparison fails
echo keep >"$T/keep.png"
run "$SC" "$T/text.png" "$T/r.png" -o "$T/keep.png"
[ "$(cat "$T/keep.png")" = keep ] || bad "a failed run replaced an output"
run "$SC" "$T/r.png"; expect_rc 2; expect_err "give a render and a photo"
run "$SC" "$T/r.png" "$T/r.png" "$T/r.png"; expect_rc 2; expect_err "unexpected argument"
run "$SC" --bogus "$T/r.png" "$T/r.png"; expect_rc 2; expect_err "Try 'skycompare --help'"
run "$SC" "$T/r.png" "$T/r.png" -o side.jpg; expect_rc 2; expect_err "must end in .png"
run "$SC" "$T/r.png" "$T/r.png" -o -; expect_rc 2; expect_err "name a file"
run "$SC" "$T/r.png" "$T/r.png" --threshold 0; expect_rc 2; expect_err "--threshold"
run "$SC" "$T/r.png" "$T/r.png" --crop 1,2,3; expect_rc 2; expect_err "--crop"
run "$SC" "$T/r.png" "$T/r.png" --mask "$T/mask.png" --horizon 3; expect_rc 2
run "$SC" "$T/r.png" "$T/r.png" --horizon 90; expect_rc 2; expect_err "--horizon 90 is below"
run "$SC" "$T/r.exr" "$T/r.png" --render-horizon 28; expect_rc 2; expect_err "--render-horizon 28 is below the 48x27 picture"
run "$SC" "$T/r.exr" "$T/r.png" --render-horizon 3 --sky-all; expect_rc 2; expect_err "contradict"
run "$SC" --series "$T/a.png" "$T/b%d.png"; expect_rc 2; expect_err "needs exactly one index conversion"
run "$SC" --first 3 "$T/r.png" "$T/r.png"; expect_rc 2; expect_err "need --series"
run "$SC" --split 0.3 "$T/r.png" "$T/r.png"; expect_rc 2; expect_err "give --overlay"
run "$SC" --overlay "$T/o.png" --split 0.3 --blend 0.5 "$T/r.png" "$T/r.png"; expect_rc 2
expect_no_file "$T/o.png"
run "$SC" --diff-range 9 "$T/r.png" "$T/r.png"; expect_rc 2; expect_err "needs --diff"
end

begin skycompare_help_matches_man_page
run "$SC" --help; expect_rc 0; expect_out "Usage: skycompare"
for o in $(grep -o -- '--[a-z][a-z-]*' "$T/out" | sort -u); do
	grep -q -- "Fl ${o#-}" "$TOP/man/skycompare.1" || bad "man page lacks $o"
done
for o in $(grep -o 'Fl -[a-z][a-z-]*' "$TOP/man/skycompare.1" | sed 's/Fl -/--/' | sort -u); do
	grep -q -- "$o" "$T/out" || bad "--help lacks $o"
done
run "$SC" --version; expect_rc 0; expect_out "skycompare (cloudscape)"
end
