# wxinterp and cloudrender stopped by Ctrl-C (SIGINT) or SIGTERM in the middle of a long
# series: it removes its temporary output and dies of the signal.
. "$TOP/tests/tools/lib.sh"
plan 4
WI="$BIN/wxinterp"
# A shell without job control starts background jobs ignoring SIGINT,
# which wxinterp then leaves ignored, as it should (nohup, batch jobs):
# env --default-signal gives the job the default disposition back.
bg_env="env --default-signal=INT,TERM"

# 25 days of hourly weather; a series of 2 days every 2 s is 86400 states,
# some seconds of work
awk 'BEGIN {
	printf "{\"metadata\":{\"name\":\"Bern\",\"latitude\":46.95,\"longitude\":7.44,\"height\":540,\"utc_timeoffset\":0},\"units\":{\"time\":\"YYYY-MM-DD hh:mm\",\"cloudcover\":\"percent\",\"precipitation\":\"mm\",\"windspeed\":\"ms-1\",\"winddirection\":\"degree\"},\"data_1h\":{\"time\":["
	n = 600
	for (i = 0; i < n; i++)
		printf "%s\"2021-06-%02d %02d:00\"", i ? "," : "", 1 + int(i / 24), i % 24
	printf "]"
	split("lowclouds midclouds highclouds precipitation windspeed winddirection", k, " ")
	for (j = 1; j <= 6; j++) {
		printf ",\"%s\":[", k[j]
		for (i = 0; i < n; i++)
			printf "%s%d", i ? "," : "", j == 5 ? 3 : j == 6 ? 250 : j == 4 ? 0 : (i * 7 + j * 13) % 90
		printf "]"
	}
	printf "}}\n"
}' >"$T/days.json"
series="--from 2021-06-01T00:00Z --to 2021-06-03T00:00Z --step 2s"

# stop SIG DIR: runs a long series into DIR/many.jsonl, sends SIG once its
# temporary exists, and leaves the exit status in $rc
stop() {
	mkdir -p "$2"
	$bg_env "$WI" $series -o "$2/many.jsonl" "$T/days.json" 2>"$T/err" &
	pid=$!
	i=0
	while [ $i -lt 200 ] && [ -z "$(ls -A "$2")" ]; do sleep 0.05; i=$((i + 1)); done
	sleep 0.3
	[ -n "$(ls -A "$2")" ] || bad "no temporary appeared in $2"
	kill -"$1" $pid
	{ wait $pid; } 2>/dev/null
	rc=$?
}

begin wxinterp_ctrl_c_leaves_no_temporary_and_exits_130
stop INT "$T/int"
expect_rc 130
expect_only_files "$T/int" 0
expect_err "wxinterp: interrupted: no output written"
end

begin wxinterp_sigterm_leaves_no_temporary_and_exits_143
stop TERM "$T/term"
expect_rc 143
expect_only_files "$T/term" 0
end

begin wxinterp_ctrl_c_to_standard_output_leaves_no_temporary
mkdir -p "$T/tmp" "$T/out"
TMPDIR="$T/tmp" $bg_env "$WI" $series "$T/days.json" >"$T/out/many.jsonl" 2>"$T/err" &
pid=$!
i=0
while [ $i -lt 200 ] && [ -z "$(ls -A "$T/tmp")" ]; do sleep 0.05; i=$((i + 1)); done
sleep 0.3
[ -n "$(ls -A "$T/tmp")" ] || bad "no temporary appeared in TMPDIR"
kill -INT $pid
{ wait $pid; } 2>/dev/null
rc=$?
expect_rc 130
expect_only_files "$T/tmp" 0
[ -s "$T/out/many.jsonl" ] && bad "part of the series reached standard output"
end

begin cloudrender_ctrl_c_in_a_series_leaves_whole_frames_and_exits_130
rm -rf "$T/out" # run's standard output goes there
# 40 states ten minutes apart; tiny frames, each a fraction of a second
"$WI" --from 2021-06-01T06:00Z --to 2021-06-01T12:30Z --step 10m "$T/days.json" \
	-o "$T/day.jsonl" || bad "wxinterp could not write the series"
FR="--size 64x36 --quality low --noise-size 16 -q -t 1 --look 200,10"
mkdir -p "$T/frames"
$bg_env "$BIN/cloudrender" --wx "$T/day.jsonl" $FR -o "$T/frames/%03d.png" 2>"$T/err" &
pid=$!
i=0
while [ $i -lt 400 ] && [ ! -e "$T/frames/001.png" ]; do sleep 0.05; i=$((i + 1)); done
kill -INT $pid
{ wait $pid; } 2>/dev/null
rc=$?
expect_rc 130
expect_err "frames written whole, no other begun"
n=$(ls -A "$T/frames" | wc -l)
[ "$n" -ge 2 ] && [ "$n" -lt 40 ] || bad "$n files after the interrupt, expected 2..39"
for f in $(ls -A "$T/frames"); do
	case $f in [0-9][0-9][0-9].png) ;; *) bad "left behind: $f" ;; esac
	pngtopnm "$T/frames/$f" >/dev/null 2>&1 || bad "$f is not a whole PNG"
done
# the same command with --skip-existing completes the series
run "$BIN/cloudrender" --wx "$T/day.jsonl" $FR --skip-existing -o "$T/frames/%03d.png"
expect_rc 0
expect_only_files "$T/frames" 40
end
