# A change of genus fades over an hour (man 1 wxinterp, GENUS CHANGES):
# the old layer thins out while the new one thickens, never a jump.
. "$TOP/tests/tools/lib.sh"
plan 5
WI="$BIN/wxinterp"
REAL="${DATA:-$TOP/../shared/data}/weather/meteoblue-basic-clouds-solar-1h.json"

# The layers of a series as lines "TIME KEY COVERAGE BASE TOP", KEY the
# genus, "fog" for a layer resting on the ground.
layers() {
	jq -r '.site.alt_m as $g | .time_utc as $t | .layers[] |
		"\($t) \(if .base_m <= $g + 1 then "fog" else .genus end) \(.coverage) \(.base_m) \(.top_m)"' "$1"
}
# steps FILE: per-step changes of each layer over a series of states:
# "TIME KEY DCOVERAGE DBASE" (a layer absent from a state has coverage 0
# and no base, and then no DBASE: "-")
steps() {
	jq -r -s '[.[] | {t: .time_utc, l: (.site.alt_m as $g | [.layers[] |
		{key: (if .base_m <= $g + 1 then "fog" else .genus end), value: .}] | from_entries)}] |
		. as $s | range(1; length) as $i | ($s[$i - 1].l) as $a | ($s[$i].l) as $b |
		(($a | keys) + ($b | keys) | unique)[] as $k |
		"\($s[$i].t) \($k) \(($b[$k].coverage // 0) - ($a[$k].coverage // 0)) \(if $a[$k] and $b[$k] then $b[$k].base_m - $a[$k].base_m else "-" end)"' "$1"
}
# The limit of a coverage change in one step of S seconds: the fade's
# weights move by at most S / 3600 s (a window of an hour), and the hourly
# data's cover by at most S / 3600 s of 100 %; 0.001 for rounding.
limit() { awk -v s="$1" 'BEGIN { printf "%.6f", 2 * s / 3600 + 0.001 }'; }

begin transition_fog_fades_into_stratocumulus_as_the_rules_say
# Bern by night (the sun below 30 degrees: stratocumulus, L7), low cover
# 40 %, fog probability 100 % until 01:00 then falling to 0 at 02:00:
# fog (L2) until 01:30, then stratocumulus.  Over the window of an hour
# centred on each time, the fog holds the part before 01:30:
#   w(t) = clamp((01:30 + 30 min - t) / 60 min, 0, 1)
# fog coverage = max(low, fog probability) w, stratocumulus 0.4 (1 - w).
printf '{"metadata":{"name":"Bern","latitude":46.95,"longitude":7.44,"height":540,"utc_timeoffset":0},"units":{"time":"YYYY-MM-DD hh:mm","cloudcover":"percent","precipitation":"mm","windspeed":"ms-1","winddirection":"degree","visibility":"m","probability":"percent"},"data_1h":{"time":["2021-06-14 00:00","2021-06-14 01:00","2021-06-14 02:00","2021-06-14 03:00"],"lowclouds":[40,40,40,40],"midclouds":[0,0,0,0],"highclouds":[0,0,0,0],"precipitation":[0,0,0,0],"windspeed":[3,3,3,3],"winddirection":[250,250,250,250],"visibility":[20000,20000,20000,20000],"fog_probability":[100,100,0,0]}}\n' >"$T/fog.json"
run "$WI" --from 2021-06-14T00:50Z --to 2021-06-14T02:10Z --step 10m "$T/fog.json"
expect_rc 0
layers "$T/out" >"$T/l"
for m in 50 60 70 80 90 100 110 120 130; do
	t=$(awk -v m="$m" 'BEGIN { printf "2021-06-14T%02d:%02d:00Z", int(m / 60), m % 60 }')
	want=$(awk -v m="$m" 'BEGIN { w = (120 - m) / 60; w = w < 0 ? 0 : w > 1 ? 1 : w
		p = m <= 60 ? 1 : m >= 120 ? 0 : (120 - m) / 60; c = p > 0.4 ? p : 0.4
		printf "%.3f %.3f", c * w, 0.4 * (1 - w) }')
	got=$(awk -v t="$t" '$1 == t && $2 == "fog" { f = $3 } $1 == t && $2 == "stratocumulus" { s = $3 }
		END { printf "%.3f %.3f", f, s }' "$T/l")
	[ "$got" = "$want" ] || bad "at $t fog and stratocumulus cover $got, expected $want"
done
grep -q ' fog [0-9.]* 540 840$' "$T/l" || bad "the fog is not 540-840 m"
grep -q ' stratocumulus [0-9.]* 1340 2040$' "$T/l" || bad "the stratocumulus is not 1340-2040 m"
end

begin transition_fade_option_sets_the_window
# --fade 2h: w(01:10) = (01:30 + 60 min - 01:10) / 120 min = 2/3; the fog's
# own coverage then max(0.4, 5/6); --fade 0: the rules of the instant
run "$WI" --at 2021-06-14T01:10Z --fade 2h "$T/fog.json"
expect_rc 0
expect_out '"layers":[{"genus":"stratus","coverage":0.556,"base_m":540,"top_m":840},{"genus":"stratocumulus","coverage":0.133,'
run "$WI" --at 2021-06-14T01:10Z --fade 0 "$T/fog.json"
expect_rc 0
expect_out '"layers":[{"genus":"stratus","coverage":0.833,"base_m":540,"top_m":840}]'
run "$WI" --at 2021-06-14T01:10Z --fade 7h "$T/fog.json"
expect_rc 2; expect_err "wxinterp: --fade: at most 6h"
end

if [ -f "$REAL" ]; then
"$WI" --step 2m "$REAL" >"$T/all.jsonl" 2>"$T/err" || echo "wxinterp failed: $(cat "$T/err")" >&2

begin transition_real_capture_changes_by_a_step_at_most
# every 2 min over the whole capture (8 days): no layer's coverage jumps,
# no base moves by more than a cumulus base follows its condensation level
[ -s "$T/all.jsonl" ] || bad "no series"
steps "$T/all.jsonl" >"$T/steps"
lim=$(limit 120)
awk -v lim="$lim" '{ d = $3 < 0 ? -$3 : $3 } d > lim { print "coverage of " $2 " changes by " $3 " at " $1; exit 1 }' \
	"$T/steps" >"$T/why" || bad "$(cat "$T/why") (limit $lim)"
awk '$4 != "-" { d = $4 < 0 ? -$4 : $4 } $4 != "-" && d > 50 { print "base of " $2 " moves " $4 " m at " $1; exit 1 }' \
	"$T/steps" >"$T/why" || bad "$(cat "$T/why")"
[ "$(wc -l <"$T/all.jsonl")" -eq 5761 ] || bad "$(wc -l <"$T/all.jsonl") states, expected 5761"
end

begin transition_real_cumulus_becomes_stratocumulus_at_sunset_gradually
# 2024-10-12: the sun sinks below 30 degrees at about 19:27 UTC; cumulus
# at 1187 m at 19:00 becomes stratocumulus at 834 m by 20:00
layers "$T/all.jsonl" | awk '$1 >= "2024-10-12T19" && $1 < "2024-10-12T20:01"' >"$T/l"
grep -q '^2024-10-12T19:00:00Z cumulus [0-9.]* 1187 ' "$T/l" || bad "no cumulus at 1187 m at 19:00"
grep -q '^2024-10-12T19:28:00Z cumulus ' "$T/l" && grep -q '^2024-10-12T19:28:00Z stratocumulus [0-9.]* 834 ' "$T/l" ||
	bad "not both cumulus and stratocumulus at 19:28"
grep -q '^2024-10-12T20:00:00Z cumulus ' "$T/l" && bad "cumulus left at 20:00"
# the cumulus thins out step by step, the stratocumulus thickens
awk '$2 == "cumulus" && $1 >= "2024-10-12T19:00" { if (c != "" && $3 > c + 0.0005) { print "cumulus grows at " $1; exit 1 } c = $3 }' \
	"$T/l" >"$T/why" || bad "$(cat "$T/why")"
end

begin transition_real_ground_fog_lifts_into_stratocumulus_gradually
# 2024-10-13: fog at 34-334 m (probability 85 % at 10:00, 3 % at 11:00)
# becomes stratocumulus at 834 m between the two hours
layers "$T/all.jsonl" | awk '$1 >= "2024-10-13T09:30" && $1 < "2024-10-13T11:31"' >"$T/l"
grep -q '^2024-10-13T10:30:00Z fog [0-9.]* 34 334$' "$T/l" && grep -q '^2024-10-13T10:30:00Z stratocumulus [0-9.]* 834 1534$' "$T/l" ||
	bad "not both fog and stratocumulus at 10:30"
awk '$2 == "fog" { n++ } END { exit !(n >= 20) }' "$T/l" || bad "the fog does not fade over many steps"
end
else
skip transition_real_capture_changes_by_a_step_at_most "no $REAL"
skip transition_real_cumulus_becomes_stratocumulus_at_sunset_gradually "no $REAL"
skip transition_real_ground_fog_lifts_into_stratocumulus_gradually "no $REAL"
fi
