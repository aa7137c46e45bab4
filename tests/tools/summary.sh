# wxinterp --summary as a user reads it, on the real meteoblue capture
# (Montevideo, 2024-10-06..14 UTC): its figures against the provider's own
# numbers, read from the file with jq.
. "$TOP/tests/tools/lib.sh"
plan 3
WX="$BIN/wxinterp"
MB="${DATA:-}/weather/meteoblue-basic-clouds-solar-1h.json"

have_data() { [ -f "$MB" ]; }
# the provider's value of data_1h.KEY at "YYYY-MM-DD hh:mm"
mb() { jq -r --arg t "$2" '.data_1h as $d | ($d.time | index($t)) as $i | $d[$k][$i]' --arg k "$1" "$MB"; }
near() { awk -v a="$1" -v b="$2" -v t="$3" 'BEGIN { d = a - b; if (d < 0) d = -d; exit !(d <= t) }'; }

begin wxinterp_summary_hours_agree_with_the_provider_file
if have_data; then
	run "$WX" --summary "$MB"; expect_rc 0
	n=$(grep -vc '^#' "$T/out")
	ref=$(jq '.data_1h.time | length' "$MB")
	[ "$n" -eq "$ref" ] || bad "$n hourly rows, the file has $ref hours"
	# the rainy evening of the 7th: 0.6 mm at 19:00 UTC under 100 % cover
	line=$(grep '^2024-10-07 19:00 ' "$T/out")
	set -- $line
	# columns: date time sun deg cover low mid high rain snow vis fog layers...
	[ "$5" = "$(mb totalcloudcover '2024-10-07 19:00')%" ] || bad "19:00 cover $5 vs the file's $(mb totalcloudcover '2024-10-07 19:00')"
	[ "$6" = "$(mb lowclouds '2024-10-07 19:00')%" ] || bad "19:00 low $6"
	[ "$7" = "$(mb midclouds '2024-10-07 19:00')%" ] || bad "19:00 mid $7"
	[ "$8" = "$(mb highclouds '2024-10-07 19:00')%" ] || bad "19:00 high $8"
	[ "$9" = "$(mb precipitation '2024-10-07 19:00')" ] || bad "19:00 rain $9 vs $(mb precipitation '2024-10-07 19:00')"
	[ "${11}" = "$(mb visibility '2024-10-07 19:00')" ] || bad "19:00 visibility ${11}"
	# the rainiest hour of the file is the row with the most rain
	top=$(jq -r '.data_1h as $d | [range(0; $d.time | length)] | max_by($d.precipitation[.]) | $d.time[.]' "$MB")
	got=$(grep -v '^#' "$T/out" | sort -k9,9g | tail -n 1 | cut -c1-16)
	[ "$got" = "$top" ] || bad "rainiest row $got, the file's rainiest hour $top"
	# every hour's rain and cover, through --json
	run "$WX" --summary --json "$MB"; expect_rc 0
	jq -s '[.[] | [.precipitation_mm_h, (.cloud_cover * 100 | round), (.cover_low * 100 | round)]]' "$T/out" >"$T/ours"
	jq '[.data_1h as $d | range(0; $d.time | length) | [$d.precipitation[.], $d.totalcloudcover[.], $d.lowclouds[.]]]' "$MB" >"$T/theirs"
	cmp -s "$T/ours" "$T/theirs" || bad "--json rain/cover differ from the file's: $(diff "$T/ours" "$T/theirs" | head -5 | tr '\n' ' ')"
	# the sun: meteoblue's isdaylight counts civil twilight as day; ours
	# is up or down by the disk's centre.  They may differ only while the
	# sun is within 6 deg below the horizon (an hour off would be 12 deg).
	odd=$(jq -s --slurpfile mb "$MB" -r '[range(0; length) as $i | .[$i] as $r
		| select($r.sun_up != ($mb[0].data_1h.isdaylight[$i] == 1))
		| select($r.sun_elevation_deg > 0 or $r.sun_elevation_deg < -6) | $r.time_utc] | join(" ")' "$T/out")
	[ -z "$odd" ] || bad "sun up/down disagrees with the file's isdaylight outside twilight at $odd"
	ups=$(jq -s '[.[] | select(.sun_up)] | length' "$T/out")
	[ "$ups" -ge 90 ] && [ "$ups" -le 100 ] || bad "$ups hours with the sun up in 8 days of October at 35 S"
	end
else
	skip wxinterp_summary_hours_agree_with_the_provider_file "no $MB (shared data absent)"
fi

begin wxinterp_summary_daily_totals_are_the_sum_of_the_hours
if have_data; then
	run "$WX" --summary --daily --json "$MB"; expect_rc 0
	for day in 2024-10-07 2024-10-11; do
		ours=$(jq -r --arg d "$day" 'select(.date_utc == $d) | .precipitation_mm' "$T/out")
		theirs=$(jq --arg d "$day" '.data_1h as $x | [range(0; $x.time | length) | select($x.time[.] | startswith($d)) | $x.precipitation[.]] | add' "$MB")
		near "$ours" "$theirs" 1e-9 || bad "$day rain $ours mm, the file's hours sum to $theirs"
		hours=$(jq -r --arg d "$day" 'select(.date_utc == $d) | .rain_hours' "$T/out")
		rh=$(jq --arg d "$day" '.data_1h as $x | [range(0; $x.time | length) | select(($x.time[.] | startswith($d)) and $x.precipitation[.] > 0)] | length' "$MB")
		[ "$hours" = "$rh" ] || bad "$day: $hours rain hours, the file has $rh"
		mx=$(jq -r --arg d "$day" 'select(.date_utc == $d) | .cloud_cover_max' "$T/out")
		rm=$(jq --arg d "$day" '.data_1h as $x | [range(0; $x.time | length) | select($x.time[.] | startswith($d)) | $x.totalcloudcover[.]] | max / 100' "$MB")
		near "$mx" "$rm" 1e-9 || bad "$day max cover $mx, the file's $rm"
	done
	run "$WX" --summary --daily "$MB"; expect_rc 0
	expect_out "# day"
	grep -q '^2024-10-07     24 ' "$T/out" || bad "no 24-hour row for 2024-10-07"
	end
else
	skip wxinterp_summary_daily_totals_are_the_sum_of_the_hours "no $MB (shared data absent)"
fi

begin wxinterp_summary_options_are_checked
run "$WX" --daily "$T/x.json"; expect_rc 2; expect_err "--daily goes with --summary"
run "$WX" --json "$T/x.json"; expect_rc 2; expect_err "--json goes with --summary"
run "$WX" --summary --daily --step 30m "$T/x.json"; expect_rc 2; expect_err "no --step with it"
run "$WX" --summary --template; expect_rc 2; expect_err "--summary describes provider files"
end
