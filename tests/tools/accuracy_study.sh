# scripts/accuracy-study as a user runs it: its usage errors, its tables
# drawn again from an accuracy.tsv, and the references' times and own error
# kept (references.tsv) and read back when the references are reused.  A
# tiny study: one scene, 16x9, 2 paths, one setting.
. "$TOP/tests/tools/lib.sh"
plan 3
STUDY="$TOP/scripts/accuracy-study"
ERR="$BIN/../bench/imgerr"

begin accuracy_study_usage_errors_say_why
for a in "--ref-seeds 3|two different seeds" "--ref-seeds 3,3|two different seeds" \
	"--ref-seeds a,b|two different seeds" "--ref-seeds 4294967296,1|two different seeds" \
	"--spp x|--spp takes a count" "--jobs 0|--jobs takes a count" \
	"--ref-device gpu|cpu or cuda" "--frobnicate|unknown option" "--scenes nope|no scene nope"; do
	# shellcheck disable=SC2086
	run "$STUDY" --build "$BIN/.." ${a%%|*} --out "$T/u"
	expect_rc 2
	expect_err "${a#*|}"
done
expect_no_file "$T/u"
run "$STUDY" --build "$BIN/.." --out
expect_rc 2
expect_err "--out needs a value"
run "$STUDY" --tables --out "$T/none"
expect_rc 1
expect_err "cannot read $T/none/accuracy.tsv"
expect_no_file "$T/none"
end

begin accuracy_study_keeps_the_references_times_and_their_own_error
"$BIN/noisebake" -q --size 16 -o "$T/noise.exr" || bad "noisebake failed"
printf '# a comment\npreset low|--quality low\n' >"$T/one.settings"
S="--build $BIN/.. --noise $T/noise.exr --scenes fog-low-sun --size 16x9 --spp 2 --settings $T/one.settings --out $T/s"
# shellcheck disable=SC2086
run "$STUDY" $S --ref-seeds 5,7
expect_rc 0
[ "$(sed 1d "$T/s/accuracy.tsv" | cut -f1-3 | tr '\t' ' ')" = "fog-low-sun preset low" ] ||
	bad "accuracy.tsv: $(cat "$T/s/accuracy.tsv")"
expect_file "$T/s/refs/fog-low-sun.16x9.2.5.exr"
expect_file "$T/s/refs/fog-low-sun.16x9.2.7.exr.time"
# the scene's line: paths, then device, seed and seconds of each, then the
# relMSE of either reference alone, as bench/imgerr computes it of the two
IFS='	' read -r sc p d1 s1 t1 d2 s2 t2 one <<L
$(sed -n 2p "$T/s/references.tsv")
L
[ "$sc $p $d1 $s1 $d2 $s2" = "fog-low-sun 2 cpu 5 cpu 7" ] || bad "references.tsv: $(cat "$T/s/references.tsv")"
for t in "$t1" "$t2"; do
	case $t in [0-9]*.[0-9][0-9]) ;; *) bad "a reference's seconds: '$t'" ;; esac
done
want=$(IMGERR_REFS=1 "$ERR" "$T/s/refs/fog-low-sun.16x9.2.5.exr" "$T/s/refs/fog-low-sun.16x9.2.5.exr" \
	"$T/s/refs/fog-low-sun.16x9.2.7.exr" | sed -n 's/^refs //p')
[ -n "$one" ] && [ "$one" = "$want" ] || bad "relmse_one '$one', imgerr says '$want'"
# reused (a GPU asked for, which this build cannot use: nothing is rendered
# again), the times and devices are the ones kept beside the references
cp "$T/s/references.tsv" "$T/refs.before"
# shellcheck disable=SC2086
run "$STUDY" $S --ref-seeds 5,7 --reuse-refs --ref-device cuda
expect_rc 0
cmp -s "$T/refs.before" "$T/s/references.tsv" ||
	bad "reused, references.tsv became $(sed -n 2p "$T/s/references.tsv")"
end

begin accuracy_study_tables_are_drawn_again_from_accuracy_tsv
# the previous case's study, or a line of our own where it failed
mkdir -p "$T/t"
if [ -s "$T/s/accuracy.tsv" ]; then
	cp "$T/s/accuracy.tsv" "$T/t/"
else
	printf 'scene\tstrategy\tsetting\tseconds\tspp\trelmse\tmare\tbias\tghi_bias\tdhi_bias\tground_bias\n' >"$T/t/accuracy.tsv"
	printf 'fog-low-sun\tpreset\tlow\t0.5\t1\t0.004\t0.1\t-0.01\t0.02\t0.02\tnone\n' >>"$T/t/accuracy.tsv"
fi
# two settings on two scenes, by hand: the geometric mean of the relMSE
# (each floored at 1e-3), the seconds summed, the worst |bias|
cat >>"$T/t/accuracy.tsv" <<'A'
fair-cumulus-noon	mine	a	2.0	1	0.04	0.3	0.05	-0.1	0.2	0.01
cumulus-thin	mine	a	3.0	1	0.01	0.3	-0.02	0.3	0.1	none
fair-cumulus-noon	mine	b	1.0	1	0.0001	0.3	0.01	0.0	0.0	-0.03
cumulus-thin	mine	b	1.0	1	0.09	0.3	0.07	0.0	0.0	0.01
A
run "$STUDY" --tables --out "$T/t" --build /nonexistent
expect_rc 0
grep -q "^mine	a	5.000	0.02	0.0500	0.3000	0.0100$" "$T/t/summary.tsv" ||
	bad "summary.tsv for mine a: $(grep '^mine	a' "$T/t/summary.tsv")"
grep -q "^mine	b	2.000	0.009487	0.0700	0.0000	0.0200$" "$T/t/summary.tsv" ||
	bad "summary.tsv for mine b: $(grep '^mine	b' "$T/t/summary.tsv")"
grep -q "^mine	b	fair-weather	2.000	0.009487	" "$T/t/classes.tsv" ||
	bad "classes.tsv: $(grep '^mine' "$T/t/classes.tsv")"
end
