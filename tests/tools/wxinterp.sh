# wxinterp as a user runs it.
. "$TOP/tests/tools/lib.sh"
plan 14
WI="$BIN/wxinterp"
REAL="${DATA:-$TOP/../shared/data}/weather/meteoblue-basic-clouds-solar-1h.json"

# num KEY: the number after "KEY": in the first line of the output
num() { head -n 1 "$T/out" | sed -n "s/.*\"$1\":\([-0-9.e+]*\).*/\1/p"; }
# near A B: |A - B| <= 1e-9 (1 + |B|)
near() { awk -v a="$1" -v b="$2" 'BEGIN { d = a - b; if (d < 0) d = -d;
	m = b < 0 ? -b : b; exit !(a != "" && d <= 1e-9 * (1 + m)) }'; }
expect_num() { v=$(num "$1"); near "$v" "$2" || bad "$1 is '$v', expected $2"; }

# meteoblue file: mb FILE NAME LAT LON OFFSET_H TIMES KEY=ARRAY...
mb() {
	f=$1 name=$2 lat=$3 lon=$4 off=$5 times=$6; shift 6
	data=""
	for kv in "$@"; do data="$data,\"${kv%%=*}\":[${kv#*=}]"; done
	printf '{"metadata":{"name":"%s","latitude":%s,"longitude":%s,"height":540,"utc_timeoffset":%s},"units":{"time":"YYYY-MM-DD hh:mm","cloudcover":"percent","precipitation":"mm","windspeed":"ms-1","winddirection":"degree","visibility":"m","probability":"percent"},"data_1h":{"time":[%s]%s}}' \
		"$name" "$lat" "$lon" "$off" "$times" "$data" >"$f"
}
H3='"2021-06-14 00:00","2021-06-14 01:00","2021-06-14 02:00"'

if [ -f "$REAL" ]; then
begin wxinterp_exact_hour_equals_the_real_data
run "$WI" "$REAL" --at 2024-10-06T07:00Z
expect_rc 0
# lowclouds 64, midclouds 0, highclouds 41, windspeed 4.09, winddirection 119,
# visibility 9460, fog_probability 6, precipitation 0 at index 7
expect_out '"layers":[{"genus":"stratocumulus","coverage":0.64,'
expect_out '{"genus":"cirrus","coverage":0.41,'
expect_num speed_m_s 4.09; expect_num from_deg 119; expect_num visibility_m 9460
expect_num fog_probability 0.06; expect_num precipitation_mm_h 0
expect_out '"time_utc":"2024-10-06T07:00:00Z"'
expect_out '"lat_deg":-34.810272,"lon_deg":-56.151733,"alt_m":34'
end

begin wxinterp_half_way_is_the_mean_of_the_real_data
run "$WI" "$REAL" --at 2024-10-06T06:30Z
expect_rc 0
# means of index 6 and 7: low (30+64)/2, high (51+41)/2, wind 4.08/4.09,
# direction 118/119, visibility 9670/9460, fog 8/6 %
expect_out '"coverage":0.47,'; expect_out '"coverage":0.46,'
# the mean 4.085 m/s written to 0.01 m/s (cloudwx(5))
awk -v v="$(num speed_m_s)" 'BEGIN { exit !(v == 4.08 || v == 4.09) }' ||
	bad "speed_m_s is '$(num speed_m_s)', expected 4.085 to 0.01"
expect_num from_deg 118.5
expect_num visibility_m 9565; expect_num fog_probability 0.07
end

begin wxinterp_outside_the_real_data_says_the_covered_range
run "$WI" "$REAL" --at 2024-10-14T00:01Z
expect_rc 1
expect_err "wxinterp: 2024-10-14T00:01:00Z is outside the data: $REAL covers 2024-10-06T00:00:00Z to 2024-10-14T00:00:00Z"
[ -s "$T/out" ] && bad "output written on error"
end

begin wxinterp_series_is_json_lines_one_state_per_step
run "$WI" "$REAL" --from 2024-10-07T10:00Z --to 2024-10-07T12:00Z --step 30m
expect_rc 0
[ "$(wc -l <"$T/out")" -eq 5 ] || bad "$(wc -l <"$T/out") lines, expected 5"
sed -n 5p "$T/out" | grep -q '"time_utc":"2024-10-07T12:00:00Z"' || bad "last line's time"
run "$WI" "$REAL"
expect_rc 0
[ "$(wc -l <"$T/out")" -eq 193 ] || bad "the whole file gave $(wc -l <"$T/out") lines, expected 193"
end

begin wxinterp_reads_stdin_and_writes_files_atomically
mkdir "$T/o"
"$WI" - --at 2024-10-08T12:00Z -o "$T/o/wx.json" <"$REAL" 2>"$T/err"; rc=$?
expect_rc 0; expect_file "$T/o/wx.json"
grep -q '"time_utc":"2024-10-08T12:00:00Z"' "$T/o/wx.json" || bad "wrong state in file"
cp "$T/o/wx.json" "$T/keep.json"
run "$WI" "$REAL" --at 2030-01-01T00:00Z -o "$T/o/wx.json"
expect_rc 1
cmp -s "$T/o/wx.json" "$T/keep.json" || bad "a failed run replaced the file"
run "$WI" "$REAL" --at 2024-10-08T12:00Z --set layer.low.coverage=7 -o "$T/o/wx.json"
expect_rc 2; expect_err "after --set: layers[0].coverage: 7 is outside 0..1"
cmp -s "$T/o/wx.json" "$T/keep.json" || bad "a failed run replaced the file"
expect_only_files "$T/o" 1
end
else
	for c in wxinterp_exact_hour_equals_the_real_data wxinterp_half_way_is_the_mean_of_the_real_data \
		wxinterp_outside_the_real_data_says_the_covered_range \
		wxinterp_series_is_json_lines_one_state_per_step \
		wxinterp_reads_stdin_and_writes_files_atomically; do
		skip $c "$REAL is absent (no shared data folder)"
	done
fi

begin wxinterp_wind_direction_across_north_passes_through_zero
mb "$T/north.json" North 46.95 7.44 2.0 "$H3" lowclouds=0,0,0 midclouds=0,0,0 \
	highclouds=0,0,0 precipitation=0,0,0 windspeed=2,4,6 winddirection=350,10,30
run "$WI" "$T/north.json" --at 2021-06-13T22:30Z     # 00:30 at UTC+2
expect_rc 0; expect_num from_deg 0; expect_num speed_m_s 3
run "$WI" "$T/north.json" --at 2021-06-13T22:15Z; expect_num from_deg 355
run "$WI" "$T/north.json" --at 2021-06-13T22:45+00:00; expect_num from_deg 5
run "$WI" "$T/north.json" --at 2021-06-14T00:00+02:00; expect_num from_deg 350
end

# One hour per genus rule (UTC, Bern, 14 June 2021: the sun is up from
# about 03:30 and 66 deg high at noon), each the rules' own (--fade 0:
# no fading of the changes between the hours).
#        00 L1 01 L2 02 L3 03 L4 04 L5 05 L7 06 M1 07 M2 08 H1 09 H2 10 H3 11 -- 12 L6
begin wxinterp_every_genus_rule_fires_on_a_crafted_day
times=""; for h in 00 01 02 03 04 05 06 07 08 09 10 11 12; do
	times="$times${times:+,}\"2021-06-14 $h:00\""; done
mb "$T/rules.json" Rules 46.95 7.44 0 "$times" \
	lowclouds=10,20,0,90,90,50,0,0,0,0,0,0,40 \
	midclouds=0,0,0,95,0,0,80,30,0,50,0,0,0 \
	highclouds=0,0,0,0,0,0,0,0,90,50,20,0,0 \
	precipitation=3,0,0.3,2.5,0.2,0,0,0,0,0,0,0,0 \
	convective_precipitation=2,0,0.3,0,0,0,0,0,0,0,0,0,0 \
	fog_probability=0,60,0,0,0,0,0,0,0,0,0,0,0 \
	visibility=30000,30000,30000,30000,30000,30000,30000,30000,30000,30000,30000,30000,30000 \
	windspeed=1,1,1,1,1,1,1,1,1,1,1,1,1 winddirection=0,0,0,0,0,0,0,0,0,0,0,0,0
run "$WI" "$T/rules.json" -v --fade 0
expect_rc 0
line() { sed -n "$((${1#0} + 1))p" "$T/out"; }
rule() { # HOUR "expected layers text" rule-text
	line "$1" | grep -qF -- "\"layers\":[$2" || bad "hour $1: $(line "$1" | sed 's/.*"layers"/layers/' | cut -c1-120), expected $2"
	grep -F "2021-06-14T$1:00:00Z" "$T/err" | grep -qF -- "$3" || bad "hour $1: -v does not name rule $3"
}
rule 00 '{"genus":"cumulonimbus","coverage":0.3,' L1
rule 01 '{"genus":"stratus","coverage":0.6,"base_m":540,"top_m":840}' L2
rule 02 '{"genus":"cumulus","coverage":0.2,' L3
rule 03 '{"genus":"nimbostratus","coverage":0.95,' L4
line 03 | grep -q altostratus && bad "hour 03: the mid cover should be in the nimbostratus"
rule 04 '{"genus":"stratus","coverage":0.9,' L5
rule 05 '{"genus":"stratocumulus","coverage":0.5,' L7
rule 06 '{"genus":"altostratus","coverage":0.8,' M1
rule 07 '{"genus":"altocumulus","coverage":0.3,' M2
rule 08 '{"genus":"cirrostratus","coverage":0.9,' H1
rule 09 '{"genus":"altocumulus","coverage":0.5,"base_m":3000,"top_m":3800},{"genus":"cirrocumulus","coverage":0.5,' H2
rule 10 '{"genus":"cirrus","coverage":0.2,' H3
rule 11 ']' "low 0%: no cover"
rule 12 '{"genus":"cumulus","coverage":0.4,' L6
end

begin wxinterp_far_site_has_its_position_name_and_layers
mb "$T/gurten.json" "" 46.92 7.44 0 "$H3" lowclouds=10,20,30 midclouds=0,0,0 \
	highclouds=0,0,0 precipitation=0,0,0 windspeed=1,1,1 winddirection=0,0,0
mb "$T/solothurn.json" "" 47.2088 7.5323 0 "$H3" lowclouds=60,70,80 midclouds=0,0,0 \
	highclouds=0,0,0 precipitation=0.5,1,1.5 windspeed=1,1,1 winddirection=0,0,0
run "$WI" "$T/gurten.json" --far "$T/solothurn.json" --far-name Solothurn \
	--site-name Gurten --alt 858 --at 2021-06-14T01:30Z
expect_rc 0
expect_out '"site":{"name":"Gurten","lat_deg":46.92,"lon_deg":7.44,"alt_m":858}'
expect_out '"far":[{"site":{"name":"Solothurn","lat_deg":47.2088,"lon_deg":7.5323,"alt_m":540},"layers":[{"genus":"nimbostratus","coverage":0.75,'
expect_out '"precipitation_mm_h":1.25,"visibility_m":30000}]'
run "$WI" "$T/gurten.json" --far "$T/solothurn.json" --at 2021-06-14T01:30Z
expect_out '"far":[{"site":{"name":"47.209N 7.532E",'    # its coordinates
run "$WI" "$T/gurten.json" --far "$T/solothurn.json" --at 2021-06-14T03:00Z
expect_rc 1; expect_err "covers 2021-06-14T00:00:00Z to 2021-06-14T02:00:00Z"
end

begin wxinterp_merges_files_of_one_site_later_file_wins
mb "$T/m1.json" M 46.95 7.44 0 "$H3" lowclouds=10,20,30 midclouds=0,0,0 \
	highclouds=0,0,0 precipitation=0,0,0 windspeed=1,1,1 winddirection=0,0,0
mb "$T/m2.json" M 46.951 7.44 0 '"2021-06-14 02:00","2021-06-14 03:00"' \
	lowclouds=50,60 midclouds=0,0 highclouds=0,0 precipitation=0,0 \
	windspeed=1,1 winddirection=0,0
run "$WI" "$T/m1.json" "$T/m2.json"
expect_rc 0
[ "$(wc -l <"$T/out")" -eq 4 ] || bad "merged series has $(wc -l <"$T/out") hours, expected 4"
sed -n 3p "$T/out" | grep -q '"coverage":0.5,' || bad "02:00 should come from the later file"
run "$WI" "$T/m1.json" "$T/north.json"
expect_rc 0
# north.json's hours are UTC+2 (22:00Z to 00:00Z), m1's UTC (00:00Z to
# 02:00Z): five hours, 00:00Z from north.json (the later file: wind 6 m/s,
# clear), 01:00Z from m1 (low cover 20 %)
[ "$(wc -l <"$T/out")" -eq 5 ] || bad "merging UTC+2 and UTC files gave $(wc -l <"$T/out") hours, expected 5"
sed -n 1p "$T/out" | grep -q '"time_utc":"2021-06-13T22:00:00Z"' || bad "the merge does not start at 22:00Z"
sed -n 3p "$T/out" | grep -q '"layers":\[\],.*"speed_m_s":6,' || bad "00:00Z is not the later file's"
sed -n 4p "$T/out" | grep -q '"coverage":0.2,' || bad "01:00Z is not m1's"
run "$WI" "$T/m1.json" "$T/solothurn.json"
expect_rc 1; expect_err "not the same site (a distant site is given with --far)"
end

begin wxinterp_nulls_are_bridged_or_reported
mb "$T/nulls.json" N 46.95 7.44 0 '"2021-06-14 00:00","2021-06-14 01:00","2021-06-14 02:00","2021-06-14 03:00","2021-06-14 04:00"' \
	lowclouds=10,null,30,null,null midclouds=0,0,0,0,0 highclouds=0,0,0,0,0 \
	precipitation=0,0,0,0,0 windspeed=1,1,1,1,1 winddirection=0,0,0,0,0
run "$WI" "$T/nulls.json" --at 2021-06-14T01:00Z
expect_rc 0; expect_out '"coverage":0.2,'
run "$WI" "$T/nulls.json" --at 2021-06-14T03:00Z
expect_rc 1
expect_err "low cloud cover (data_1h.lowclouds) has no value at 2021-06-14T03:00:00Z: it is null from 2021-06-14T03:00:00Z to the end of the data"
run "$WI" "$T/nulls.json" --at 2021-06-14T01:00Z --max-gap 1h
expect_rc 1; expect_err "are 2 h apart (at most 1 h are bridged: --max-gap)"
end

begin wxinterp_provider_problems_are_data_errors
printf '{"error":true,"reason":"Cannot initialize WeatherVariable from invalid String value tempeture_2m for key hourly"}' >"$T/e1.json"
run "$WI" "$T/e1.json" --at 2021-06-14T00:00Z
expect_rc 1; expect_err "wxinterp: $T/e1.json: provider error (reason): Cannot initialize WeatherVariable from invalid String value tempeture_2m for key hourly"
printf '{"error_message":"MB_REQUEST::DISPATCH: Invalid api key"}' >"$T/e2.json"
run "$WI" "$T/e2.json"; expect_rc 1; expect_err "provider error (error_message): MB_REQUEST::DISPATCH: Invalid api key"
printf '<html><head><title>503 Service Unavailable</title></head></html>' >"$T/e3.json"
run "$WI" "$T/e3.json"; expect_rc 1; expect_err 'an HTML page, not JSON: "503 Service Unavailable"'
head -c 300 "$T/north.json" >"$T/e4.json"
run "$WI" "$T/e4.json"; expect_rc 1; expect_err "truncated JSON: the text ends at byte 300"
sed 's/"2021-06-14 02:00"/"2021-06-14 03:00"/' "$T/north.json" >"$T/e5.json"
run "$WI" "$T/e5.json"; expect_rc 1
expect_err 'data_1h.time[2]: "2021-06-14 03:00" is 2 h after time[1] "2021-06-14 01:00"'
sed 's/"lowclouds":\[0,0,0\]/"lowclouds":[0,0]/' "$T/north.json" >"$T/e6.json"
run "$WI" "$T/e6.json"; expect_rc 1
expect_err "data_1h.lowclouds: 2 values but time has 3 (index 2 has no value)"
run "$WI" "$T/nope.json"; expect_rc 1; expect_err "nope.json"
end

begin wxinterp_template_and_play_mode
run "$WI" --template
expect_rc 0; expect_out '"schema": "cloudwx/2",'
expect_out '{"genus": "cumulus", "coverage": 0.35, "base_m": 1500, "top_m": 2700}'
cp "$T/out" "$T/tpl.json"
run "$WI" --template --at 2022-07-01T12:00+02:00 --set layer.low.coverage=0.8 \
	--set precipitation=2.5 --set visibility=5000 --set wind.speed=3 \
	--set layer.high=none --set layer.mid=altostratus --site-name Gurten
expect_rc 0
expect_out '"time_utc": "2022-07-01T10:00:00Z"'
expect_out '"name": "Gurten"'
expect_out '{"genus": "cumulus", "coverage": 0.8, "base_m": 1500, "top_m": 2700},'
expect_out '{"genus": "altostratus", "coverage": 0.5,'
expect_out '"precipitation_mm_h": 2.5,'; expect_out '"visibility_m": 5000,'
expect_out '"wind": {"speed_m_s": 3, "from_deg": 250}'
grep -q cirrus "$T/out" && bad "layer.high=none left the cirrus"
run "$WI" --template --from 2021-06-14T00:00Z --to 2021-06-14T01:00Z --step 15m
expect_rc 0
[ "$(wc -l <"$T/out")" -eq 5 ] || bad "template series: $(wc -l <"$T/out") lines, expected 5"
run "$WI" --template --set convective=3
expect_rc 2; expect_err "wxinterp: after --set: convective_mm_h: 3 is outside 0..0"
run "$WI" --template --set layer.low.colour=3
expect_rc 2; expect_err "wxinterp: --set layer.low.colour=3: a layer has the fields genus, coverage, base_m and top_m"
run "$WI" --template --set layers[4].coverage=0.3
expect_rc 2; expect_err "no layer 4 (the state has 2; layers[2]=GENUS adds one)"
end

begin wxinterp_bad_options_are_usage_errors
for args in "" "--at 2021-06-14T00:00 x.json" "--at tomorrow x.json" \
	"--step 0 x.json" "--step 10x x.json" "--max-gap 30m x.json" "--alt 10000 x.json" \
	"--far-name X x.json" "--at 2021-06-14T00:00Z --from 2021-06-14T00:00Z x.json" \
	"--at 2021-06-14T00:00Z --step 1h x.json" "--template x.json" \
	"--template --from 2021-06-14T00:00Z" "--set nonsense x.json" "--bogus" \
	"--far a --far b --far c --far d --far e x.json" "- --far - --at 2021-06-14T00:00Z"; do
	# shellcheck disable=SC2086
	(cd "$T" && "$WI" $args >"$T/out" 2>"$T/err" </dev/null); rc=$?
	[ "$rc" -eq 2 ] || bad "'$args' exited $rc, expected 2"
	grep -q '^wxinterp: \|^Try ' "$T/err" || bad "'$args' gave no 'wxinterp:' message"
done
run "$WI" "$T/north.json" --from 2021-06-14T02:00Z --to 2021-06-14T01:00Z
expect_rc 2; expect_err "ends (2021-06-14T01:00:00Z) before it starts"
run "$WI" "$T/north.json" --pretty
expect_rc 2; expect_err "--pretty writes one state, not a series of 3"
end

begin wxinterp_help_and_version
run "$WI" --help; expect_rc 0; expect_out "Usage: wxinterp"
for o in --output --at --from --to --step --far --far-name --site-name --alt \
	--max-gap --set --template --pretty --quiet --verbose --help --version; do
	grep -q -- "$o" "$T/out" || bad "--help lacks $o"
	grep -q -- "Fl ${o#-}" "$TOP/man/wxinterp.1" || bad "man page lacks $o"
done
run "$WI" --version; expect_rc 0; expect_out "wxinterp (cloudscape)"
end
