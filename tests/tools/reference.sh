# cloudrender's reference integrator and the accuracy study's knobs, as a
# user runs them.
. "$TOP/tests/tools/lib.sh"
plan 5
CR="$BIN/cloudrender"
SMALL="--size 24x14 --noise-size 16 -q"
rse() { grep -o '"median":[0-9.]*' "$T/err" | head -1 | cut -d: -f2; }

begin reference_integrator_is_deterministic_for_any_thread_count
run "$CR" $SMALL --integrator reference --spp 4 -t 1 -o "$T/a.exr"
expect_rc 0
run "$CR" $SMALL --integrator reference --spp 4 -t 2 -o "$T/b.exr"
expect_rc 0
cmp -s "$T/a.exr" "$T/b.exr" || bad "1 and 2 threads give different images"
run "$CR" $SMALL --integrator reference --spp 4 --seed 9 -o "$T/c.exr"
same_pixels "$T/a.exr" "$T/c.exr" && bad "another seed gives the same image"
run "$CR" $SMALL -o "$T/m.exr"
same_pixels "$T/a.exr" "$T/m.exr" && bad "the reference renders what the march renders, byte for byte"
end

begin reference_stats_report_the_noise_and_it_falls
# --stats reports the relative standard error of the pixels; with 16 times
# the paths it is smaller (the 1/sqrt(n) law itself is tests/unit/
# test_reference.c's: the variance estimate of a few paths per pixel
# misses the rare bright paths, so its median understates the error there)
run "$CR" $SMALL --integrator reference --spp 4 --stats -o "$T/a.png"
expect_rc 0
expect_err '"integrator":"reference"'
e4=$(rse)
run "$CR" $SMALL --integrator reference --spp 64 --stats -o "$T/a.png"
e64=$(rse)
awk -v a="$e4" -v b="$e64" 'BEGIN { exit !(b > 0 && a > 1.2 * b) }' ||
	bad "error at 4 paths $e4, at 64 paths $e64: not smaller"
end

begin reference_and_knob_options_are_checked
for a in "--integrator nope" "--spp 0" "--max-bounces -1" "--march fast" \
	"--light-march spiral" "--max-steps 0" "--min-transmittance 0.9"; do
	# shellcheck disable=SC2086
	run "$CR" $SMALL $a -o "$T/x.png"
	expect_rc 2
	expect_no_file "$T/x.png"
done
run "$CR" $SMALL --integrator nope -o "$T/x.png"
expect_err "is not march or reference"
end

begin knobs_change_the_picture_the_way_they_say
mean() { pngtopnm "$1" | pamsumm -mean -brief; }
# single scattering (max bounces 1: no sky light on what the eye sees, no
# light between the clouds) is darker than all orders
run "$CR" $SMALL --integrator reference --spp 8 --max-bounces 1 -o "$T/one.png"
expect_rc 0
run "$CR" $SMALL --integrator reference --spp 8 -o "$T/all.png"
awk -v a="$(mean "$T/one.png")" -v b="$(mean "$T/all.png")" 'BEGIN { exit !(a < 0.8 * b) }' ||
	bad "single scattering is not darker than all orders"
# the naive sum and the quadratic light march see the same clouds, differently
run "$CR" $SMALL --march naive --no-jitter -o "$T/n.exr"
expect_rc 0
run "$CR" $SMALL --no-jitter -o "$T/s.exr"
same_pixels "$T/n.exr" "$T/s.exr" && bad "--march naive renders what the standard march renders"
run "$CR" $SMALL --no-jitter --light-march quadratic -o "$T/q.exr"
same_pixels "$T/q.exr" "$T/s.exr" && bad "--light-march quadratic changes nothing"
run "$CR" $SMALL --no-jitter --light-march cone -o "$T/c.exr"
expect_rc 0
same_pixels "$T/c.exr" "$T/s.exr" && bad "--light-march cone changes nothing"
run "$CR" $SMALL --no-jitter --march adaptive -o "$T/a.exr"
expect_rc 0
same_pixels "$T/a.exr" "$T/s.exr" && bad "--march adaptive changes nothing"
# without the haze's light the view down to the far ground is darker
run "$CR" $SMALL --look 150,-2 -o "$T/h.png"
run "$CR" $SMALL --look 150,-2 --no-haze -o "$T/nh.png"
expect_rc 0
awk -v a="$(mean "$T/nh.png")" -v b="$(mean "$T/h.png")" 'BEGIN { exit !(a < b) }' ||
	bad "--no-haze does not darken the hazy distance"
end

begin imgerr_refs_is_either_references_own_error
# bench/imgerr with IMGERR_REFS: the relMSE of one of two references of the
# same paths, sum (A - B)^2 / 2 over sum A B, the channels' values from
# the files themselves (exrpixels, hexadecimal floats read by printf)
ERR=$BIN/../bench/imgerr
run "$CR" $SMALL --integrator reference --spp 4 --seed 1 -o "$T/a.exr"
run "$CR" $SMALL --integrator reference --spp 4 --seed 2 -o "$T/b.exr"
expect_rc 0
for f in a b; do
	# shellcheck disable=SC2046
	printf '%.17g\n' $("$HELPERS/exrpixels" "$T/$f.exr" R G B | sed 1d) >"$T/$f.txt"
done
want=$(paste "$T/a.txt" "$T/b.txt" |
	awk '{ d += ($1 - $2) * ($1 - $2); s += $1 * $2 } END { printf "%.6g", d / 2 / s }')
got=$(IMGERR_REFS=1 "$ERR" "$T/a.exr" "$T/a.exr" "$T/b.exr" | sed -n 's/^refs //p')
awk -v g="$got" -v w="$want" 'BEGIN { exit !(w > 0 && g > 0.999 * w && g < 1.001 * w) }' ||
	bad "IMGERR_REFS gave ${got:-nothing}, the pixels $want"
# the first line is still the test against the references: A against A
# and B is no error at all
set -- $(IMGERR_REFS=1 "$ERR" "$T/a.exr" "$T/a.exr" "$T/b.exr" | head -1)
[ "$1" = 0 ] || bad "A against A and B: relMSE $1, not 0"
end
