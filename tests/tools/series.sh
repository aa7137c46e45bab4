# cloudrender over a series of weather states, as a user runs it: one frame
# a state, names numbered as ffmpeg numbers them, slices, resuming after a
# kill, and the caption.
. "$TOP/tests/tools/lib.sh"
plan 9
CR="$BIN/cloudrender"
FAST="--size 48x27 --quality low --noise-size 16 -q"
state() { # hour coverage
	printf '{"schema":"cloudwx/1","time_utc":"2021-06-14T%s:00:00Z","site":{"name":"Bern","lat_deg":46.95,"lon_deg":7.44,"alt_m":540},"layers":[{"genus":"cumulus","coverage":%s,"base_m":1500,"top_m":2700}]}\n' "$@"
}
{ state 09 0.3; echo; state 12 0.5; state 15 0.7; } >"$T/s.jsonl" # a blank line between
png_meta() { gdalinfo -json "$1" 2>/dev/null | jq -r '.metadata[""].cloudscape // empty'; }

begin series_renders_every_state_as_its_own_frame
mkdir "$T/f"
run "$CR" --wx "$T/s.jsonl" --look 200,10 $FAST -o "$T/f/%05d.png" -o "$T/f/%05d.exr"
expect_rc 0
[ "$(ls "$T/f" | tr '\n' ' ')" = "00000.exr 00000.png 00001.exr 00001.png 00002.exr 00002.png " ] ||
	bad "frames: $(ls -A "$T/f" | tr '\n' ' ')"
# each frame is what that state alone renders, byte for byte (the noise
# and all that is made once serve every frame alike)
i=0
for line in 1 3 4; do
	sed -n "${line}p" "$T/s.jsonl" >"$T/one.json"
	run "$CR" --wx "$T/one.json" --look 200,10 $FAST -o "$T/one.png" -o "$T/one.exr"
	expect_rc 0
	cmp -s "$T/one.png" "$T/f/0000$i.png" || bad "frame $i is not state $((i + 1)) (PNG)"
	cmp -s "$T/one.exr" "$T/f/0000$i.exr" || bad "frame $i is not state $((i + 1)) (EXR)"
	i=$((i + 1))
done
same_pixels "$T/f/00000.png" "$T/f/00002.png" && bad "the first and last states look the same"
# standard input too
mkdir "$T/g"
"$CR" --wx - --look 200,10 $FAST -o "$T/g/%d.png" <"$T/s.jsonl" 2>"$T/err"; rc=$?
expect_rc 0
for i in 0 1 2; do
	cmp -s "$T/g/$i.png" "$T/f/0000$i.png" || bad "--wx - frame $i differs"
done
end

begin series_on_threads_writes_frames_while_the_next_ones_render
# six states: on 8 threads four frames are written at once while the next
# ones render; the files are those of one thread byte for byte, and -v and
# --stats report the frames in their order, each with its own layers
i=3
for h in 09 10 11 12 13 14; do state "$h" "0.$i"; i=$((i + 1)); done >"$T/six.jsonl"
mkdir "$T/t1" "$T/t8"
run "$CR" --wx "$T/six.jsonl" --look 200,10 $FAST -t 1 -o "$T/t1/%d.png" -o "$T/t1/%d.exr"
expect_rc 0
run "$CR" --wx "$T/six.jsonl" --look 200,10 $FAST -t 8 -v --stats -o "$T/t8/%d.png" \
	-o "$T/t8/%d.exr"
expect_rc 0
covers=$(sed -n 's/.*"layers":\[{"genus":"cumulus","coverage":\([0-9.]*\),.*/\1/p' "$T/err" |
	tr '\n' ' ')
[ "$covers" = "0.300 0.400 0.500 0.600 0.700 0.800 " ] ||
	bad "--stats gave the frames' layers covers '$covers'"
for i in 0 1 2 3 4 5; do
	cmp -s "$T/t1/$i.png" "$T/t8/$i.png" || bad "frame $i's PNG differs on 8 threads"
	cmp -s "$T/t1/$i.exr" "$T/t8/$i.exr" || bad "frame $i's EXR differs on 8 threads"
done
order=$(sed -n 's/^cloudrender: frame \([0-9]*\) (.*/\1/p' "$T/err" | tr '\n' ' ')
[ "$order" = "0 1 2 3 4 5 " ] || bad "frames reported as '$order'"
expect_err "6 frames rendered in"
[ "$(ls "$T/t8" | wc -l)" -eq 12 ] || bad "$(ls -A "$T/t8" | tr '\n' ' ')"
# resumed: the frames skipped are reported in order with those rendered
rm "$T/t8/1.png" "$T/t8/4.exr"
run "$CR" --wx "$T/six.jsonl" --look 200,10 $FAST -t 8 -v --skip-existing \
	-o "$T/t8/%d.png" -o "$T/t8/%d.exr"
expect_rc 0
order=$(sed -n 's/^cloudrender: frame \([0-9]*\)[ :].*/\1/p' "$T/err" | tr '\n' ' ')
[ "$order" = "0 1 2 3 4 5 " ] || bad "frames reported as '$order' on resuming"
cmp -s "$T/t1/1.png" "$T/t8/1.png" && cmp -s "$T/t1/4.exr" "$T/t8/4.exr" ||
	bad "the resumed frames differ"
end

begin series_keeps_the_default_view_of_its_first_state
mkdir "$T/d"
run "$CR" --wx "$T/s.jsonl" $FAST -o "$T/d/%d.png"
expect_rc 0
# the default view looks away from the sun, which moves 09:00 -> 15:00;
# the series holds the first state's look in every frame
sed -n 1p "$T/s.jsonl" >"$T/first.json"
sed -n 4p "$T/s.jsonl" >"$T/last.json"
run "$CR" --wx "$T/first.json" $FAST -o "$T/first.png"; expect_rc 0
run "$CR" --wx "$T/last.json" $FAST -o "$T/last.png"; expect_rc 0
az() { png_meta "$1" | jq -r .camera.azimuth_deg; }
a0=$(az "$T/first.png"); alast=$(az "$T/last.png")
[ "$a0" != "$alast" ] || bad "the sun did not move the default view ($a0): the case tests nothing"
for i in 0 1 2; do
	[ "$(az "$T/d/$i.png")" = "$a0" ] || bad "frame $i looks at azimuth $(az "$T/d/$i.png"), the first state's default $a0"
done
end

begin series_names_frames_as_ffmpeg_numbers_them
mkdir "$T/n"
run "$CR" --wx "$T/s.jsonl" $FAST --start-number 98 -o "$T/n/a%03d-100%%.png"
expect_rc 0
[ "$(ls "$T/n" | tr '\n' ' ')" = "a098-100%.png a099-100%.png a100-100%.png " ] ||
	bad "names: $(ls -A "$T/n" | tr '\n' ' ')"
# ffmpeg itself would read them back as frames 98..100 (where installed)
end

begin series_refuses_what_cannot_name_its_frames
check_bad() { # message args...
	msg=$1; shift
	run "$CR" --wx "$T/s.jsonl" $FAST "$@"
	expect_rc 2; expect_err "$msg"
}
check_bad "3 frames need a frame number in the name" -o "$T/x.png"
check_bad "'%s' at byte" -o "$T/x%s.png"
check_bad "more than one frame number" -o "$T/x%d-%d.png"
check_bad "standard output takes one frame" -o -
check_bad "--time sets the time of one state" --time 2021-06-14T12:00Z -o "$T/x%d.png"
check_bad "select none of the series' 3 states (frames 0:3)" --frames 3:9 -o "$T/x%d.png"
check_bad "--frames 2:2: no frame" --frames 2:2 -o "$T/x%d.png"
check_bad "'%.' at byte" -o "$T/100%.png"
ls "$T" | grep -q '^x' && bad "a refused run wrote $(ls "$T" | grep '^x')"
# one frame needs no number: a single state, or a slice of one
run "$CR" --wx "$T/first.json" $FAST -o "$T/single.png"; expect_rc 0; expect_file "$T/single.png"
run "$CR" --wx "$T/s.jsonl" --look 200,10 $FAST --frames 2 -o "$T/two.png"; expect_rc 0
cmp -s "$T/two.png" "$T/f/00002.png" || bad "--frames 2 is not the third state's frame"
end

begin series_frames_selects_a_slice_by_the_names_numbers
for spec in "1:3=1 2" "2:=2" ":1=0" "1=1" "0:99=0 1 2"; do
	rm -rf "$T/s"; mkdir "$T/s"
	run "$CR" --wx "$T/s.jsonl" --look 200,10 $FAST --frames "${spec%%=*}" -o "$T/s/%d.png"
	expect_rc 0
	got=$(ls "$T/s" | sed 's/\.png$//' | sort -n | tr '\n' ' ')
	[ "$got" = "${spec#*=} " ] || bad "--frames ${spec%%=*} wrote frames $got, expected ${spec#*=}"
done
# with --start-number the slice counts in the names' numbers
rm -rf "$T/s"; mkdir "$T/s"
run "$CR" --wx "$T/s.jsonl" --look 200,10 $FAST --start-number 10 --frames 11:12 -o "$T/s/%d.png"
expect_rc 0
[ "$(ls "$T/s")" = "11.png" ] || bad "--start-number 10 --frames 11:12 wrote $(ls "$T/s")"
cmp -s "$T/s/11.png" "$T/f/00001.png" || bad "frame 11 is not the second state"
end

begin series_skip_existing_resumes_a_killed_run
# eight frames slow enough to stop midway: one thread, 160x90
for h in 10 11 12 13 14 15 16 17; do state "$h" 0.5; done >"$T/k.jsonl"
SLOW="--size 160x90 --quality low --noise-size 16 -t 1 --look 200,10"
mkdir "$T/ref" "$T/k"
run "$CR" --wx "$T/k.jsonl" $SLOW -q -o "$T/ref/%02d.png"; expect_rc 0
"$CR" --wx "$T/k.jsonl" $SLOW -q -o "$T/k/%02d.png" 2>/dev/null &
pid=$!
n=0
while [ ! -e "$T/k/01.png" ] && [ $n -lt 600 ]; do sleep 0.05; n=$((n + 1)); done
kill -KILL $pid 2>/dev/null
wait $pid 2>/dev/null
before=$(ls "$T/k" | tr '\n' ' ')
had=$(ls "$T/k" | wc -l)
[ "$had" -ge 2 ] && [ "$had" -lt 8 ] || bad "the kill left $had frames ($before): the case needs a run stopped midway"
ls -li "$T/k" | grep -v '^total' | awk '{ print $1, $NF }' | sort -k2,2 >"$T/inodes-before"
run "$CR" --wx "$T/k.jsonl" $SLOW -v --skip-existing -o "$T/k/%02d.png"
expect_rc 0
# the rerun rendered exactly the frames that were missing
rendered=$(sed -n 's/^cloudrender: frame \([0-9]*\) (.*/\1/p' "$T/err" | tr '\n' ' ')
expected=""
for i in 0 1 2 3 4 5 6 7; do
	[ -e "$T/ref/0$i.png" ] && case " $before " in *" 0$i.png "*) ;; *) expected="$expected$i " ;; esac
done
echo "# killed with: $before; the rerun rendered: $rendered"
[ "$rendered" = "$expected" ] || bad "the rerun rendered frames '$rendered', the missing ones were '$expected'"
grep -q "skipped, its outputs exist" "$T/err" || bad "no frame said it was skipped"
# the frames there before are untouched, and the series is whole and right
ls -li "$T/k" | grep -v '^total' | awk '{ print $1, $NF }' | sort -k2,2 >"$T/inodes-after"
join -j 2 "$T/inodes-before" "$T/inodes-after" | awk '$2 != $3 { print $1 }' | grep -q . &&
	bad "frames there before were written again"
for i in 0 1 2 3 4 5 6 7; do
	cmp -s "$T/k/0$i.png" "$T/ref/0$i.png" || bad "frame $i differs from an uninterrupted run's"
done
[ "$(ls "$T/k" | wc -l)" -eq 8 ] || bad "$(ls "$T/k" | wc -l) frames, expected 8"
# a third run has nothing to do
run "$CR" --wx "$T/k.jsonl" $SLOW -v --skip-existing -o "$T/k/%02d.png"
expect_rc 0; expect_err "0 frames rendered"
end

begin series_skip_existing_writes_only_the_missing_outputs
mkdir "$T/m"
run "$CR" --wx "$T/s.jsonl" --look 200,10 $FAST -o "$T/m/%d.png"; expect_rc 0
rm "$T/m/1.png"
echo keep >"$T/m/2.png"
run "$CR" --wx "$T/s.jsonl" --look 200,10 $FAST --skip-existing -o "$T/m/%d.png" -o "$T/m/%d.exr"
expect_rc 0
[ "$(cat "$T/m/2.png")" = keep ] || bad "an existing output was replaced"
cmp -s "$T/m/1.png" "$T/f/00001.png" || bad "the missing frame 1 was not written as it should be"
for i in 0 1 2; do expect_file "$T/m/$i.exr"; done
end

begin series_caption_stamps_the_lower_left_corner
printf '{"schema":"cloudwx/1","time_utc":"2021-06-14T15:00:00Z","site":{"name":"Bern","lat_deg":46.95,"lon_deg":7.44,"alt_m":540},"layers":[{"genus":"cumulus","coverage":0.6,"base_m":1500,"top_m":2700}]}\n' >"$T/c.json"
CAP="--wx $T/c.json --size 320x90 --quality low --noise-size 16 -q --look 200,10"
# shellcheck disable=SC2086
run "$CR" $CAP -o "$T/plain.png" -o "$T/plain.exr"; expect_rc 0
# shellcheck disable=SC2086
run "$CR" $CAP --caption -o "$T/cap.png" -o "$T/cap.exr"; expect_rc 0
pngtopnm -plain "$T/plain.png" | tr -s ' \n' '\n\n' | sed '/^$/d' | tail -n +5 >"$T/p1"
pngtopnm -plain "$T/cap.png" | tr -s ' \n' '\n\n' | sed '/^$/d' | tail -n +5 >"$T/p2"
# 3 lines at scale 1 (90 rows): the box is rows 53..85, from column 4; the
# first glyph, '2' of 2021, at column 8, rows 57..63: the HD44780 ROM's 5x7
# '2' is rows 01110 10001 00001 00010 00100 01000 11111
paste -d ' ' "$T/p1" "$T/p2" | awk -v W=320 '
	{ k = NR - 1; px = int(k / 3); x = px % W; y = int(px / W)
	  if ($1 != $2) { changed++; if (x < 4 || y < 53 || y > 85) outside++ }
	  if (k % 3 == 0) white[x "," y] = ($2 == 255)
	  if (k % 3 == 2) white[x "," y] = white[x "," y] && ($2 == 255) }
	END {
	  split("01110 10001 00001 00010 00100 01000 11111", row, " ")
	  for (r = 1; r <= 7; r++) for (c = 1; c <= 5; c++) {
		want = substr(row[r], c, 1) == "1"
		if (white[(7 + c) "," (56 + r)] != want) wrong++
	  }
	  printf "changed %d outside %d glyph_wrong %d\n", changed, outside, wrong
	  exit !(changed > 500 && outside == 0 && wrong == 0) }' >"$T/cap" ||
	bad "the caption is not where or what it should be: $(cat "$T/cap")"
echo "# caption: $(cat "$T/cap")"
# the EXR shows it too: opaque letters, their radiance white on the display
"$HELPERS/exrpixel" "$T/cap.exr" 9 57 R A >"$T/e" 2>&1 || bad "exrpixel: $(cat "$T/e")"
awk 'NR == 2 { exit !($1 >= 127 && $1 <= 129 && $2 == 1) }' "$T/e" ||
	bad "the EXR's glyph pixel is $(sed -n 2p "$T/e"), expected R 128 A 1"
same_pixels "$T/plain.exr" "$T/cap.exr" && bad "--caption changed nothing in the EXR"
end
