# Clouds that drift with the wind, as a user makes a time-lapse: wxinterp
# writes each state's drift (the integral of the wind), cloudrender moves
# the cloud field by it.  Pictures are compared by their cloud alpha
# (tests/helpers/alphashift: the shift that best carries one onto the
# other).
. "$TOP/tests/tools/lib.sh"
plan 7
WI="$BIN/wxinterp"
CR="$BIN/cloudrender"
AS="$HELPERS/alphashift"
REAL="${DATA:-$TOP/../shared/data}/weather/meteoblue-basic-clouds-solar-1h.json"

# meteoblue file: mb FILE TIMES KEY=ARRAY... (Bern, 540 m, UTC)
mb() {
	f=$1 times=$2; shift 2
	data=""
	for kv in "$@"; do data="$data,\"${kv%%=*}\":[${kv#*=}]"; done
	printf '{"metadata":{"name":"Bern","latitude":46.95,"longitude":7.44,"height":540,"utc_timeoffset":0},"units":{"time":"YYYY-MM-DD hh:mm","cloudcover":"percent","precipitation":"mm","windspeed":"ms-1","winddirection":"degree","visibility":"m","probability":"percent"},"data_1h":{"time":[%s]%s}}' \
		"$times" "$data" >"$f"
}
H3='"2021-06-14 10:00","2021-06-14 11:00","2021-06-14 12:00"'
# a sheet of altocumulus, 50 %, and a wind: mid_file FILE SPEED FROM
mid_file() {
	mb "$1" "$H3" lowclouds=0,0,0 midclouds=50,50,50 highclouds=0,0,0 \
		precipitation=0,0,0 windspeed="$2,$2,$2" winddirection="$3,$3,$3"
}
# A thin layer (3000-3100 m, 2460-2560 m above the camera) seen straight
# up through a 60-degree lens on 160 pixels: 2 x 2510 m x tan 30 / 160 =
# 18.11 m a pixel at its middle; east is to the left, north up.
thin="--set layer.mid.base=3000 --set layer.mid.top=3100"
look_up="--camera 46.95,7.44,540 --look 0,90 --fov 60 --size 160x160 --quality low --no-haze --noise-size 32 -q -t 2"
MPP=18.113
# The clouds move with the 10-m wind times (height / 10 m)^(1/7) at the
# genus's typical height: altocumulus 3000-3800 m, 2860 m above the ground.
ALOFT=$(awk 'BEGIN { printf "%.6f", exp(log(286) / 7) }')
# shift A B: "DX DY C" of alphashift within 30 pixels
shift_of() { "$AS" "$1" "$2" 30 | sed -n 's/^shift //p'; }
# within V EXPECTED TOL
within() { awk -v v="$1" -v e="$2" -v t="$3" 'BEGIN { d = v - e; if (d < 0) d = -d; exit !(v != "" && d <= t) }'; }

begin advection_drift_is_the_wind_integrated_from_the_first_hour
mid_file "$T/w.json" 3 270
run "$WI" --at 2021-06-14T11:30Z "$T/w.json"
expect_rc 0
# 3 m/s from the west for 1.5 h: 16200 m east
expect_out '"drift":{"since_utc":"2021-06-14T10:00:00Z","east_m":16200,"north_m":0,"axis_deg":90}'
expect_out '"schema":"cloudwx/2"'
# moved 10 min on by --set, the state's wind carries it 1800 m further
run "$WI" --at 2021-06-14T11:30Z --set time_utc=2021-06-14T11:40Z "$T/w.json"
expect_rc 0
expect_out '"east_m":18000,"north_m":0,'
end

begin advection_a_state_at_a_time_is_that_of_any_series_holding_it
# a wind that turns and speeds up: the drift is an integral, not a product
mb "$T/turn.json" '"2021-06-14 10:00","2021-06-14 11:00","2021-06-14 12:00","2021-06-14 13:00"' \
	lowclouds=0,0,0,0 midclouds=50,50,50,50 highclouds=0,0,0,0 precipitation=0,0,0,0 \
	windspeed=2,7.5,3,9 winddirection=350,40,200,190
"$WI" --at 2021-06-14T11:42Z "$T/turn.json" >"$T/at" || bad "--at failed"
"$WI" --from 2021-06-14T10:00Z --to 2021-06-14T13:00Z --step 6m "$T/turn.json" >"$T/s1" || bad "series 1 failed"
"$WI" --from 2021-06-14T11:41:30Z --to 2021-06-14T11:43Z --step 30s "$T/turn.json" >"$T/s2" || bad "series 2 failed"
grep -qxF "$(cat "$T/at")" "$T/s1" || bad "series every 6 min lacks the --at state"
grep -qxF "$(cat "$T/at")" "$T/s2" || bad "series every 30 s lacks the --at state"
grep -q '"east_m":0,"north_m":0' "$T/at" && bad "no drift"
end

begin advection_a_minute_later_the_picture_is_moved_by_the_wind
mid_file "$T/w.json" 3 270
"$WI" --from 2021-06-14T11:00Z --to 2021-06-14T11:01Z --step 1m $thin "$T/w.json" >"$T/m.jsonl" || bad "wxinterp failed"
sed -n 1p "$T/m.jsonl" >"$T/m0.json"; sed -n 2p "$T/m.jsonl" >"$T/m1.json"
"$CR" --wx "$T/m0.json" $look_up -o "$T/m0.exr" && "$CR" --wx "$T/m1.json" $look_up -o "$T/m1.exr" ||
	bad "cloudrender failed"
set -- $(shift_of "$T/m0.exr" "$T/m1.exr")
# 3 m/s x 60 s x aloft factor, east = left
want=$(awk -v a="$ALOFT" -v m="$MPP" 'BEGIN { printf "%.3f", -3 * 60 * a / m }')
within "$1" "$want" 0.6 || bad "moved $1 px across, expected $want (the wind's 60 s)"
within "$2" 0 0.5 || bad "moved $2 px north-south, expected 0"
awk -v c="$3" 'BEGIN { exit !(c >= 0.98) }' || bad "moved picture correlates $3, not the same clouds"
end

begin advection_a_wind_faster_by_0.2_percent_moves_clouds_0.2_percent_of_the_way
# two forecasts 0.2 % apart in speed, two hours after their first hour
mid_file "$T/a.json" 3 270
mid_file "$T/b.json" 3.006 270
"$WI" --at 2021-06-14T12:00Z $thin "$T/a.json" >"$T/a.wx" && "$WI" --at 2021-06-14T12:00Z $thin "$T/b.json" >"$T/b.wx" ||
	bad "wxinterp failed"
"$CR" --wx "$T/a.wx" $look_up -o "$T/a.exr" && "$CR" --wx "$T/b.wx" $look_up -o "$T/b.exr" || bad "cloudrender failed"
set -- $(shift_of "$T/a.exr" "$T/b.exr")
# 0.2 % of 3 m/s x 7200 s, aloft
want=$(awk -v a="$ALOFT" -v m="$MPP" 'BEGIN { printf "%.3f", -0.002 * 3 * 7200 * a / m }')
within "$1" "$want" 0.5 || bad "moved $1 px, expected $want (0.2 % of the drift)"
within "$2" 0 0.5 || bad "moved $2 px north-south, expected 0"
awk -v c="$3" 'BEGIN { exit !(c >= 0.98) }' || bad "correlates $3 after the shift: the sky was reshuffled"
end

begin advection_a_wind_turned_by_0.2_degree_moves_clouds_little
# 0.2 degree more from the north-west and 0.2 % faster: the drift grows by
# 0.2 % along the field's axis, which turns by 0.2 degree about the camera
# (0.0035 x 1.4 km = 5 m, 0.3 px, at the picture's edge)
mb "$T/c.json" "$H3" lowclouds=0,0,0 midclouds=50,50,50 highclouds=0,0,0 \
	precipitation=0,0,0 windspeed=3.006,3.006,3.006 winddirection=270.2,270.2,270.2
"$WI" --at 2021-06-14T12:00Z $thin "$T/c.json" >"$T/c.wx" || bad "wxinterp failed"
"$CR" --wx "$T/c.wx" $look_up -o "$T/c.exr" || bad "cloudrender failed"
set -- $(shift_of "$T/a.exr" "$T/c.exr")
want=$(awk -v a="$ALOFT" -v m="$MPP" 'BEGIN { printf "%.3f", -0.002 * 3 * 7200 * a / m }')
within "$1" "$want" 0.6 || bad "moved $1 px, expected $want"
within "$2" 0 0.6 || bad "moved $2 px north-south, expected 0"
awk -v c="$3" 'BEGIN { exit !(c >= 0.98) }' || bad "correlates $3 after the shift: the sky was reshuffled"
end

begin advection_cloudwx_1_states_render_as_before
# a cloudwx/1 state and the same as cloudwx/2 without a drift render the
# same bytes (the wind times the time since 2000, as cloudwx/1 always did)
printf '{"schema":"cloudwx/1","time_utc":"2021-06-14T15:00:00Z","site":{"lat_deg":46.95,"lon_deg":7.44,"alt_m":540},"layers":[{"genus":"cumulus","coverage":0.5,"base_m":1500,"top_m":2700}],"wind":{"speed_m_s":4,"from_deg":250},"drift":{"since_utc":"2021-06-14T00:00:00Z","east_m":5,"north_m":0,"axis_deg":0}}\n' >"$T/v1.json"
sed 's|cloudwx/1|cloudwx/2|; s|,"drift":{[^}]*}||' "$T/v1.json" >"$T/v2.json"
sed 's|cloudwx/1|cloudwx/2|' "$T/v1.json" >"$T/v2d.json"
fast="--size 64x36 --quality low --noise-size 16 -q -t 1"
"$CR" --wx "$T/v1.json" $fast -o "$T/v1.png" && "$CR" --wx "$T/v2.json" $fast -o "$T/v2.png" &&
	"$CR" --wx "$T/v2d.json" $fast -o "$T/v2d.png" || bad "cloudrender failed: $(cat "$T/err" 2>/dev/null)"
cmp -s "$T/v1.png" "$T/v2.png" || bad "cloudwx/1 renders unlike cloudwx/2 without a drift"
cmp -s "$T/v1.png" "$T/v2d.png" && bad "a cloudwx/2 drift is ignored"
end

if [ -f "$REAL" ]; then
begin advection_real_frames_10_s_apart_are_the_same_clouds_moved
# 15:01:10 -> 15:01:20 of 2024-10-13: the wind's written speed turns 3.44
# -> 3.45 m/s there, which once reshuffled the whole sky
"$WI" --from 2024-10-13T15:01:10Z --to 2024-10-13T15:01:20Z --step 10s "$REAL" >"$T/r.jsonl" || bad "wxinterp failed"
sed -n 1p "$T/r.jsonl" >"$T/r0.json"; sed -n 2p "$T/r.jsonl" >"$T/r1.json"
grep -q '"speed_m_s":3.44' "$T/r0.json" && grep -q '"speed_m_s":3.45' "$T/r1.json" ||
	bad "the written speed does not change here any more"
view="--look 0,60 --size 160x90 --quality low --noise-size 32 -q -t 2"
"$CR" --wx "$T/r0.json" $view -o "$T/r0.exr" && "$CR" --wx "$T/r1.json" $view -o "$T/r1.exr" || bad "cloudrender failed"
c=$("$AS" "$T/r0.exr" "$T/r1.exr" 4 | sed -n 's/^shift [^ ]* [^ ]* //p')
awk -v c="$c" 'BEGIN { exit !(c >= 0.95) }' || bad "best-shift correlation $c: not the same clouds"
end
else
skip advection_real_frames_10_s_apart_are_the_same_clouds_moved "no $REAL"
fi
