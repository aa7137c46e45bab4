# mbfetch as a user runs it, against the scripted local server
# (tests/helpers/httpd.c) on 127.0.0.1: never the real providers.
. "$TOP/tests/tools/lib.sh"
plan 33
MB="$BIN/mbfetch"
KEY=tEsTkEy0123456789abcdef
export MBFETCH_APIKEY="$KEY" HOME="$T/home" no_proxy='*' NO_PROXY='*'
unset XDG_CONFIG_HOME http_proxy https_proxy HTTP_PROXY HTTPS_PROXY ALL_PROXY all_proxy
mkdir "$T/home"
# short waits everywhere: the whole file runs in a few seconds
FAST="--retry-delay-ms 10 --connect-timeout 2 --timeout 5"

# ---- fixtures: small synthetic responses ----
# vals VALUE COUNT: "VALUE, VALUE, ..." COUNT times
vals() { s=""; j=0; while [ "$j" -lt "$2" ]; do s="$s${s:+, }$1"; j=$((j + 1)); done; printf '%s' "$s"; }
# mb_json N [ok|nulls|short|gap] [NAME]: a meteoblue basic-1h_clouds-1h reply
mb_json() {
	n=$1 v=${2:-ok} times="" i=0
	while [ "$i" -lt "$n" ]; do
		h=$i; [ "$v" = gap ] && [ "$i" -ge 3 ] && h=$((i + 1))
		times="$times${times:+, }\"2026-04-20 $(printf %02d "$h"):00\""
		i=$((i + 1))
	done
	low=$(vals 20 "$n")
	[ "$v" = short ] && low=$(vals 20 $((n - 1)))
	[ "$v" = nulls ] && low="null, $(vals 20 $((n - 1)))"
	sun=$(vals 30 "$n"); [ "$v" = nulls ] && sun=$(vals null "$n")
	cat <<EOF
{"metadata": {"name": "${3:-}", "latitude": 46.95, "longitude": 7.45, "height": 540,
 "timezone_abbrevation": "UTC", "utc_timeoffset": 0.0, "modelrun_utc": "2026-04-20 00:00",
 "modelrun_updatetime_utc": "2026-04-20 02:10", "generation_time_ms": 3.2},
"units": {"time": "YYYY-MM-DD hh:mm", "temperature": "C", "windspeed": "ms-1",
 "winddirection": "degree", "precipitation": "mm", "cloudcover": "percent",
 "relativehumidity": "percent", "visibility": "m", "probability": "percent",
 "pressure": "hPa", "precipitation_probability": "percent", "sunshinetime": "minutes"},
"data_1h": {"time": [$times],
 "temperature": [$(vals 12.5 "$n")], "felttemperature": [$(vals 11.0 "$n")],
 "precipitation": [$(vals 0.0 "$n")], "convective_precipitation": [$(vals 0.0 "$n")],
 "precipitation_probability": [$(vals 10 "$n")], "snowfraction": [$(vals 0.0 "$n")],
 "windspeed": [$(vals 3.2 "$n")], "winddirection": [$(vals 250 "$n")],
 "relativehumidity": [$(vals 70 "$n")], "sealevelpressure": [$(vals 1015.2 "$n")],
 "pictocode": [$(vals 3 "$n")], "isdaylight": [$(vals 1 "$n")], "uvindex": [$(vals 2 "$n")],
 "rainspot": [$(vals '"0000000000000000000000000000000000000000000000000"' "$n")],
 "totalcloudcover": [$(vals 40 "$n")], "lowclouds": [$low], "midclouds": [$(vals 30 "$n")],
 "highclouds": [$(vals 10 "$n")], "visibility": [$(vals 20000 "$n")],
 "fog_probability": [$(vals 5 "$n")], "sunshinetime": [$sun]}}
EOF
}
# om_json N: an Open-Meteo forecast reply with the variables mbfetch asks for
om_json() {
	n=$1 times="" i=0
	while [ "$i" -lt "$n" ]; do
		times="$times${times:+, }\"2026-04-20T$(printf %02d "$i"):00\""; i=$((i + 1))
	done
	cat <<EOF
{"latitude": 46.94, "longitude": 7.44, "generationtime_ms": 0.5, "utc_offset_seconds": 0,
 "timezone": "GMT", "timezone_abbreviation": "GMT", "elevation": 540.0,
 "hourly_units": {"time": "iso8601", "cloud_cover": "%", "cloud_cover_low": "%",
  "cloud_cover_mid": "%", "cloud_cover_high": "%", "precipitation": "mm",
  "showers": "mm", "wind_speed_10m": "m/s", "wind_direction_10m": "°", "visibility": "m",
  "relative_humidity_2m": "%", "temperature_2m": "°C", "is_day": ""},
 "hourly": {"time": [$times], "cloud_cover": [$(vals 40 "$n")],
  "cloud_cover_low": [$(vals 20 "$n")], "cloud_cover_mid": [$(vals 30 "$n")],
  "cloud_cover_high": [$(vals 10 "$n")], "precipitation": [$(vals 0.1 "$n")],
  "showers": [$(vals 0.0 "$n")],
  "wind_speed_10m": [$(vals 3.5 "$n")], "wind_direction_10m": [$(vals 240 "$n")],
  "visibility": [$(vals 24140.0 "$n")], "relative_humidity_2m": [$(vals 71 "$n")],
  "temperature_2m": [$(vals 9.8 "$n")], "is_day": [$(vals 1 "$n")]}}
EOF
}

# ---- the server's script: DIR/CASE/N is the N-th answer for /CASE/... ----
S="$T/srv"
# resp CASE N: the answer file from standard input
resp() { mkdir -p "$S/$1"; cat >"$S/$1/$2"; }
json200() { printf '200 OK\nContent-Type: application/json\n\n'; }

{ json200; mb_json 6; } | resp mbok 1
{ json200; om_json 6; } | resp omok 1
{ json200; mb_json 6; } >"$T/mbok.json"
mb_json 6 >"$T/mb6.json"
om_json 6 >"$T/om6.json"
printf '400 Bad Request\nContent-Type: application/json\n\n{"error":true,"reason":"Cannot initialize WeatherVariable from invalid String value tempeture_2m for key hourly"}' | resp om400 1
printf '401 Unauthorized\nContent-Type: application/json\n\n{"error_message": "MB_REQUEST::DISPATCH: Invalid api key (request @QUERY@)"}' | resp mb401 1
printf '200 OK\nContent-Type: application/json\n\n{"error_message": "MB_REQUEST::DISPATCH: This datafeed is not authorized for your api key"}' | resp mbnosolar 1
printf '429 Too Many Requests\nContent-Type: application/json\n\n{"reason":"Daily API request limit exceeded. Please try again tomorrow.","error":true}' | resp om429day 1
printf '429 Too Many Requests\nContent-Type: application/json\n\n{"reason":"Minutely API request limit exceeded. Please try again in one minute.","error":true}' | resp om429min 1
printf '429 Too Many Requests\nRetry-After: 1\nContent-Type: application/json\n\n{"error_message":"slow down"}' | resp mb429after 1
{ json200; mb_json 6; } | resp mb429after 2
printf '500 Internal Server Error\nContent-Type: text/plain\n\nbackend down' | resp mb500 1
printf '502 Bad Gateway\nContent-Type: text/plain\n\nbad gateway' | resp mb500 2
{ json200; mb_json 6; } | resp mb500 3
printf '503 Service Unavailable\nContent-Type: text/html\n\n<html><head><title>503 Service Unavailable</title></head><body><h1>Service Unavailable</h1><p>for @QUERY@</p></body></html>' | resp mb503 1
printf '200 OK\nContent-Type: text/html\n\n<!DOCTYPE html><html><body><h1>Maintenance</h1><p>Back at 14:00 &amp; later</p></body></html>' | resp mbhtml 1
{ json200; mb_json 6 | head -c 700; } | resp mbtrunc 1
{ printf '200 OK\nContent-Type: application/json\nContent-Length: 5000\n\n'; mb_json 6 | head -c 700; } | resp mbcut 1
printf '200 OK\nContent-Type: application/json\nX-Test-Repeat: 20000\n\n[0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0]' | resp mbbig 1
printf '200 OK\nContent-Type: application/json\nX-Test-Repeat: 20000\nX-Test-No-Length: 1\n\n[0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0]' | resp mbbigstream 1
printf '200 OK\nX-Test-Hang: 1\n\n' | resp mbhang 1
{ json200; mb_json 6 short; } | resp mbshort 1
{ json200; mb_json 6 nulls; } | resp mbnulls 1
{ json200; mb_json 6 gap; } | resp mbgap 1
{ json200; mb_json 6 ok '@QUERY@'; } | resp mbecho 1
{ json200; om_json 6; } | resp omcache 1
{ json200; om_json 6; } | resp mbwrong 1
{ json200; om_json 6 | sed 's|"wind_speed_10m": "m/s"|"wind_speed_10m": "km/h"|'; } | resp omkmh 1

"$HELPERS/httpd" "$S" --log "$T/req.log" --lifetime 60 >"$T/port" 2>"$T/httpd.err" &
srv=$!
trap 'kill "$srv" 2>/dev/null; chmod -R u+w "$T" 2>/dev/null; rm -rf "$T"' EXIT
i=0
while [ ! -s "$T/port" ] && [ "$i" -lt 100 ]; do sleep 0.05; i=$((i + 1)); done
BASE="http://127.0.0.1:$(cat "$T/port")"
: >>"$T/req.log"

# requests CASE: how many requests the server got for CASE
requests() { grep -c "^$1 " "$T/req.log"; }
expect_requests() { # CASE N
	n=$(requests "$1"); [ "$n" -eq "$2" ] || bad "$n requests to $1, expected $2"
}
# a folder with a good output already in it, which a failure must not touch
fresh() { rm -rf "$T/o"; mkdir "$T/o"; printf 'keep\n' >"$T/o/out.json"; }
expect_kept() {
	[ "$(cat "$T/o/out.json")" = keep ] || bad "existing output clobbered"
	expect_only_files "$T/o" 1
}
expect_no_key() { # FILE...: none holds the key
	for f in "$@"; do
		! grep -qF "$KEY" "$f" || bad "$(basename "$f") holds the API key"
	done
}
expect_no_err() { ! grep -qF -- "$1" "$T/err" || bad "stderr holds '$1'"; }

if [ ! -s "$T/port" ]; then
	# the project's own server: not starting is a failure, not a skip
	fail_case mbfetch_local_server "the test server did not start: $(cat "$T/httpd.err")"
	exit 1
fi

begin mbfetch_meteoblue_success_writes_validated_json
fresh
run "$MB" $FAST --base-url "$BASE/mbok" --site gurten --days 2 --history-days 1 -o "$T/o/out.json"
expect_rc 0
cmp -s "$T/o/out.json" "$T/mb6.json" || bad "output differs from what the server sent"
expect_only_files "$T/o" 1
expect_requests mbok 1
for p in /mbok/packages/basic-1h_clouds-1h? lat=46.91722 lon=7.44361 asl=858 tz=UTC \
	format=json windspeed=ms-1 temperature=C precipitationamount=mm winddirection=degree \
	forecast_days=2 history_days=1 "apikey=$KEY"; do
	grep "^mbok " "$T/req.log" | grep -qF -- "$p" || bad "request lacks $p"
done
expect_no_key "$T/err" "$T/out"
end

begin mbfetch_openmeteo_success_needs_no_key
MBFETCH_APIKEY='' run "$MB" $FAST --provider open-meteo --base-url "$BASE/omok" \
	--lat 46.95 --lon 7.45 --days 3 --history-days 2
expect_rc 0
cmp -s "$T/out" "$T/om6.json" || bad "standard output differs from what the server sent"
for p in /omok/v1/forecast? latitude=46.95 longitude=7.45 wind_speed_unit=ms timezone=GMT \
	past_days=2 forecast_days=3 \
	hourly=cloud_cover,cloud_cover_low,cloud_cover_mid,cloud_cover_high,precipitation,showers,snowfall,wind_speed_10m,wind_direction_10m,visibility,relative_humidity_2m,temperature_2m,is_day; do
	grep "^omok " "$T/req.log" | grep -qF -- "$p" || bad "request lacks $p"
done
grep "^omok " "$T/req.log" | grep -q apikey && bad "a key went to Open-Meteo"
grep "^omok " "$T/req.log" | grep -q elevation && bad "--lat/--lon without --asl sent an elevation"
end

begin mbfetch_400_is_a_bad_request_reported_verbatim_not_retried
fresh
run "$MB" $FAST --provider open-meteo --base-url "$BASE/om400" -o "$T/o/out.json"
expect_rc 4
expect_err "mbfetch: request rejected (open-meteo, HTTP 400 Bad Request): Cannot initialize WeatherVariable from invalid String value tempeture_2m for key hourly"
expect_requests om400 1
expect_kept
end

begin mbfetch_401_reports_provider_message_without_key
fresh
run "$MB" $FAST -v --base-url "$BASE/mb401" -o "$T/o/out.json"
expect_rc 3
expect_err "authentication failed (meteoblue, HTTP 401 Unauthorized): MB_REQUEST::DISPATCH: Invalid api key"
expect_err "apikey=REDACTED"
expect_err "the key came from MBFETCH_APIKEY"
expect_requests mb401 1
expect_no_key "$T/err" "$T/out"
expect_kept
end

begin mbfetch_radiation_asks_for_solar_1h_and_names_it_when_refused
fresh
run "$MB" $FAST --radiation --base-url "$BASE/mbnosolar" -o "$T/o/out.json"
expect_rc 3
grep "^mbnosolar " "$T/req.log" | grep -qF "/packages/basic-1h_clouds-1h_solar-1h?" ||
	bad "the request lacks the solar-1h package"
expect_err "This datafeed is not authorized for your api key"
expect_err "the request included meteoblue's solar-1h package (--radiation), which the key may not cover: try without --radiation"
expect_no_key "$T/err"
expect_kept
end

begin mbfetch_429_daily_limit_is_not_retried
fresh
run "$MB" $FAST --provider open-meteo --base-url "$BASE/om429day" -o "$T/o/out.json"
expect_rc 5
expect_err "rate limit exceeded (open-meteo, HTTP 429 Too Many Requests): Daily API request limit exceeded. Please try again tomorrow. (not retried: the daily limit resets at 00:00 UTC)"
expect_requests om429day 1
expect_kept
end

begin mbfetch_429_minutely_limit_waits_a_minute_or_gives_up
fresh
run "$MB" $FAST --retry-max-wait 1 --provider open-meteo --base-url "$BASE/om429min" -o "$T/o/out.json"
expect_rc 5
expect_err "Minutely API request limit exceeded"
expect_err "the server asks to wait 60 s, longer than --retry-max-wait 1 s"
expect_requests om429min 1
expect_kept
end

begin mbfetch_429_retry_after_is_honoured
fresh
run "$MB" $FAST --base-url "$BASE/mb429after" -o "$T/o/out.json"
expect_rc 0
expect_err "rate limit exceeded (meteoblue, HTTP 429 Too Many Requests): slow down; retrying in 1 s (attempt 2 of 4)"
expect_requests mb429after 2
cmp -s "$T/o/out.json" "$T/mb6.json" || bad "output differs from the second answer"
end

begin mbfetch_5xx_then_success_is_retried_with_backoff
fresh
run "$MB" $FAST --base-url "$BASE/mb500" -o "$T/o/out.json"
expect_rc 0
expect_err "server error (meteoblue, HTTP 500 Internal Server Error): backend down; retrying in 0.01 s (attempt 2 of 4)"
expect_err "server error (meteoblue, HTTP 502 Bad Gateway): bad gateway; retrying in 0.02 s (attempt 3 of 4)"
expect_requests mb500 3
cmp -s "$T/o/out.json" "$T/mb6.json" || bad "output differs from the third answer"
run "$MB" -q $FAST --base-url "$BASE/mb500" -o "$T/o/out.json"
expect_rc 0
[ -s "$T/err" ] && bad "-q still printed: $(cat "$T/err")"
end

begin mbfetch_persistent_5xx_html_is_a_network_error_after_retries
fresh
run "$MB" -v $FAST --retries 2 --base-url "$BASE/mb503" -o "$T/o/out.json"
expect_rc 6
expect_err "server error (meteoblue, HTTP 503 Service Unavailable): 503 Service Unavailable Service Unavailable for lat="
expect_err "after 3 attempts"
expect_requests mb503 3
expect_no_key "$T/err"
expect_no_err "<title>"
expect_kept
end

begin mbfetch_html_error_page_is_invalid_data
fresh
run "$MB" $FAST --base-url "$BASE/mbhtml" -o "$T/o/out.json"
expect_rc 7
expect_err "the response is HTML, not JSON: Maintenance Back at 14:00 & later"
expect_requests mbhtml 1
expect_kept
end

begin mbfetch_truncated_json_is_invalid_data
fresh
run "$MB" $FAST --base-url "$BASE/mbtrunc" -o "$T/o/out.json"
expect_rc 7
expect_err "the response is not valid JSON (it ends early, at byte 700): {\"metadata\": {"
expect_kept
end

begin mbfetch_transfer_cut_short_is_retried_then_a_network_error
fresh
run "$MB" $FAST --retries 1 --base-url "$BASE/mbcut" -o "$T/o/out.json"
expect_rc 6
expect_err "network error:"
expect_requests mbcut 2
expect_kept
end

begin mbfetch_oversized_body_is_aborted
fresh
run "$MB" $FAST --max-bytes 100k --base-url "$BASE/mbbig" -o "$T/o/out.json"
expect_rc 7
expect_err "the response is larger than 102400 bytes (--max-bytes); transfer aborted"
expect_requests mbbig 1
run "$MB" $FAST --max-bytes 100k --base-url "$BASE/mbbigstream" -o "$T/o/out.json"
expect_rc 7
expect_err "the response is larger than 102400 bytes"
expect_requests mbbigstream 1
expect_kept
end

begin mbfetch_silent_server_times_out
fresh
run "$MB" --timeout 0.4 --retries 1 --retry-delay-ms 10 --base-url "$BASE/mbhang" -o "$T/o/out.json"
expect_rc 6
expect_err "network error: Operation timed out after"
expect_err "after 2 attempts"
expect_requests mbhang 2
expect_kept
end

begin mbfetch_arrays_of_different_length_are_invalid
fresh
run "$MB" $FAST --base-url "$BASE/mbshort" -o "$T/o/out.json"
expect_rc 7
expect_err "mbfetch: data_1h.lowclouds: 5 values but time has 6"
expect_kept
end

begin mbfetch_nulls_are_accepted_and_kept
fresh
run "$MB" $FAST --base-url "$BASE/mbnulls" -o "$T/o/out.json"
expect_rc 0
grep -q '"lowclouds": \[null, 20' "$T/o/out.json" || bad "the null in lowclouds is gone"
grep -q '"sunshinetime": \[null, null' "$T/o/out.json" || bad "the nulls in sunshinetime are gone"
end

begin mbfetch_units_other_than_requested_are_invalid
# a provider that ignored wind_speed_unit=ms: km/h would pass for m/s
fresh
run "$MB" $FAST --provider open-meteo --base-url "$BASE/omkmh" -o "$T/o/out.json"
expect_rc 7
expect_err 'hourly_units.wind_speed_10m: unit "km/h" is not the one cloudscape requests (expected "m/s")'
expect_kept
end

begin mbfetch_two_hour_gap_in_time_is_invalid
fresh
run "$MB" $FAST --base-url "$BASE/mbgap" -o "$T/o/out.json"
expect_rc 7
expect_err "mbfetch: data_1h.time[3]: \"2026-04-20 04:00\" is 2 h after time[2]"
expect_kept
end

begin mbfetch_echoed_key_is_never_printed_or_written
fresh
run "$MB" -v $FAST --base-url "$BASE/mbecho" --cache "$T/cache" -o "$T/o/out.json"
expect_rc 0
expect_err "the response held the API key; it was replaced by REDACTED"
grep -qF 'apikey=REDACTED' "$T/o/out.json" || bad "the echoed request is not in the output, redacted"
"$MB" --check "$T/o/out.json" >/dev/null 2>&1 || bad "the redacted output is not valid"
expect_no_key "$T/err" "$T/out" "$T/o/out.json" "$T"/cache/*
leaks=$(grep -rlF "$KEY" "$T" | grep -v -e "/req.log\$" -e "/srv/")
[ -z "$leaks" ] || bad "the key is in $leaks"
end

begin mbfetch_key_file_must_be_private
printf '%s\n' "$KEY" >"$T/home/key"; chmod 644 "$T/home/key"
fresh
MBFETCH_APIKEY='' run "$MB" $FAST --key-file "$T/home/key" --base-url "$BASE/mbok" -o "$T/o/out.json"
expect_rc 3
expect_err "key file $T/home/key is accessible by group or others (mode 0644); refusing to use it: run 'chmod 600 $T/home/key'"
expect_kept
chmod 600 "$T/home/key"
MBFETCH_APIKEY='' run "$MB" $FAST --key-file "$T/home/key" --base-url "$BASE/mbok" -o "$T/o/out.json"
expect_rc 0
tail -n 1 "$T/req.log" | grep -qF "apikey=$KEY" || bad "the key from the file was not sent"
# the default key file, found through HOME
mkdir -p "$T/home/.config/cloudscape"; cp "$T/home/key" "$T/home/.config/cloudscape/meteoblue.key"
chmod 600 "$T/home/.config/cloudscape/meteoblue.key"
MBFETCH_APIKEY='' run "$MB" $FAST --base-url "$BASE/mbok" -o "$T/o/out.json"
expect_rc 0
chmod 640 "$T/home/.config/cloudscape/meteoblue.key"
MBFETCH_APIKEY='' run "$MB" $FAST --base-url "$BASE/mbok" -o "$T/o/out.json"
expect_rc 3; expect_err "(mode 0640)"
rm -rf "$T/home/.config"
expect_no_key "$T/err" "$T/out"
end

begin mbfetch_without_a_key_says_where_to_put_one
fresh
MBFETCH_APIKEY='' run "$MB" $FAST --base-url "$BASE/mbok" -o "$T/o/out.json"
expect_rc 3
expect_err "no API key: set MBFETCH_APIKEY or write the key to $T/home/.config/cloudscape/meteoblue.key (mode 600), or use --provider open-meteo"
MBFETCH_APIKEY='' run "$MB" --key-file "$T/nope.key" --base-url "$BASE/mbok" -o "$T/o/out.json"
expect_rc 3; expect_err "cannot read key file $T/nope.key: No such file"
expect_kept
end

begin mbfetch_wrong_provider_data_is_invalid
fresh
run "$MB" $FAST --base-url "$BASE/mbwrong" -o "$T/o/out.json"
expect_rc 7; expect_err "expected meteoblue data, got open-meteo data"
expect_kept
end

begin mbfetch_unreachable_server_is_a_network_error
fresh
# port 1 on the loopback: nothing listens there
run "$MB" --retries 0 --connect-timeout 1 --base-url "http://127.0.0.1:1" -o "$T/o/out.json"
expect_rc 6; expect_err "network error:"
expect_kept
end

begin mbfetch_cache_serves_a_fresh_response
rm -rf "$T/cache"
run "$MB" $FAST --provider open-meteo --base-url "$BASE/omcache" --cache "$T/cache" -o "$T/c1.json"
expect_rc 0
run "$MB" -v $FAST --provider open-meteo --base-url "$BASE/omcache" --cache "$T/cache" -o "$T/c2.json"
expect_rc 0; expect_err "using the cache $T/cache/open-meteo-"
expect_requests omcache 1
cmp -s "$T/c1.json" "$T/c2.json" || bad "the cached copy differs"
run "$MB" $FAST --provider open-meteo --base-url "$BASE/omcache" --cache "$T/cache" \
	--cache-max-age 0 -o "$T/c3.json"
expect_rc 0; expect_requests omcache 2
run "$MB" $FAST --provider open-meteo --days 2 --base-url "$BASE/omcache" --cache "$T/cache" -o "$T/c4.json"
expect_rc 0; expect_requests omcache 3
expect_only_files "$T/cache" 2
run "$MB" $FAST --provider open-meteo --base-url "$BASE/omcache" -o "$T/c5.json"
expect_rc 0; expect_requests omcache 4
end

begin mbfetch_check_reports_each_problem_with_field_and_index
run "$MB" --check "$T/mb6.json" "$T/om6.json"
expect_rc 0
expect_out "$T/mb6.json: ok: meteoblue, 6 hours, 2026-04-20T00:00:00Z to 2026-04-20T05:00:00Z"
expect_out "$T/om6.json: ok: open-meteo, 6 hours"
mb_json 6 gap | sed 's/"midclouds": \[30/"midclouds": [130/' >"$T/bad.json"
run "$MB" --check "$T/mb6.json" "$T/bad.json"
expect_rc 7
expect_err "mbfetch: $T/bad.json: data_1h.time[3]:"
expect_err "mbfetch: $T/bad.json: data_1h.midclouds[0]: 130 is outside 0..100"
expect_err "mbfetch: $T/bad.json: invalid: 2 problems"
run "$MB" --check - <"$T/mb6.json"; expect_rc 0; expect_out "-: ok: meteoblue"
run "$MB" --check "$T/none.json"; expect_rc 1; expect_err "No such file"
end

begin mbfetch_warns_of_an_unencrypted_key_unless_the_host_is_this_machine
fresh
run "$MB" $FAST --base-url "$BASE/mbok" --site gurten --days 2 --history-days 1 -o "$T/o/out.json"
expect_rc 0; expect_no_err "unencrypted"
# a name that merely begins with localhost is somebody else's host
run "$MB" --retries 0 --connect-timeout 1 --timeout 2 \
	--base-url "http://localhost.example.invalid/x" --site gurten -o "$T/o/out2.json"
expect_err "sending the API key unencrypted over http"
[ "$rc" -ne 0 ] || bad "a fetch from an invalid host succeeded"
end

begin mbfetch_check_accepts_the_real_meteoblue_capture
real="$DATA/weather/meteoblue-basic-clouds-solar-1h.json"
if [ -f "$real" ]; then
	run "$MB" --check "$real"
	expect_rc 0
	expect_out "ok: meteoblue, 193 hours, 2024-10-06T00:00:00Z to 2024-10-14T00:00:00Z"
	end
else
	skip mbfetch_check_accepts_the_real_meteoblue_capture "no $real"
fi

begin mbfetch_dry_run_prints_the_request_with_the_key_redacted
run "$MB" --dry-run --site Solothurn --days 7
expect_rc 0
expect_out "https://my.meteoblue.com/packages/basic-1h_clouds-1h?lat=47.20791&lon=7.53714&asl=432&name=Solothurn&tz=UTC&format=json&temperature=C&windspeed=ms-1&winddirection=degree&precipitationamount=mm&forecast_days=7&apikey=REDACTED"
run "$MB" --dry-run --provider open-meteo --lat 46.5 --lon 7 --asl 1200
expect_rc 0
expect_out "https://api.open-meteo.com/v1/forecast?latitude=46.5&longitude=7&elevation=1200&hourly="
end

begin mbfetch_lists_sites
run "$MB" --list-sites
expect_rc 0
for s in Bern Solothurn Fribourg Gurten Bantiger; do expect_out "$s"; done
expect_out "46.91722   7.44361   858 m"
end

begin mbfetch_bad_options_are_usage_errors
for args in "--site Atlantis" "--lat 91 --lon 0" "--lat 46" "--site bern --lat 46 --lon 7" \
	"--days 8" "--days 17 --provider open-meteo" "--history-days 5" "--days 0" \
	"--provider dwd" "--timeout 0" "--retries -1" "--retries 101" "--max-bytes 0" \
	"--max-bytes 2G" "--max-bytes x" "--base-url ftp://x" "--base-url http://h/?a=1" \
	"--check" "--check -o x.json a.json" "--check --site bern a.json" "--bogus" \
	"$KEY" "--retry-delay-ms -5" "--asl 10000"; do
	# shellcheck disable=SC2086
	(cd "$T" && "$MB" --dry-run $args >"$T/out" 2>"$T/err"); rc=$?
	[ "$rc" -eq 2 ] || bad "'$args' exited $rc, expected 2"
	grep -q '^mbfetch: \|^Try ' "$T/err" || bad "'$args' gave no 'mbfetch:' message"
done
expect_no_key "$T/err"
[ ! -e "$T/x.json" ] || bad "a usage error left x.json"
end

begin mbfetch_unwritable_output_spends_no_request
n0=$(requests mbok)
run "$MB" $FAST --base-url "$BASE/mbok" -o "$T/missing/out.json"
expect_rc 1; expect_err "mbfetch: cannot create $T/missing/out.json"
[ "$(requests mbok)" -eq "$n0" ] || bad "a request was made for an unwritable output"
end

begin mbfetch_help_and_version
run "$MB" --help; expect_rc 0; expect_out "Usage: mbfetch"
for o in --output --provider --site --lat --lon --asl --days --history-days --key-file \
	--base-url --connect-timeout --timeout --retries --retry-delay-ms --retry-max-wait \
	--max-bytes --cache --cache-max-age --dry-run --check --list-sites --quiet \
	--verbose --help --version MBFETCH_APIKEY; do
	grep -q -- "$o" "$T/out" || bad "--help lacks $o"
	case $o in --*) grep -q -- "Fl ${o#-}" "$TOP/man/mbfetch.1" || bad "man page lacks $o" ;; esac
done
for code in 3 4 5 6 7; do
	grep -q "^\.It $code\$" "$TOP/man/mbfetch.1" || bad "man page lacks exit status $code"
done
run "$MB" --version; expect_rc 0; expect_out "mbfetch (cloudscape)"
end
