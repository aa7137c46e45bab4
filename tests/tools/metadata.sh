# What a frame says it shows: cloudrender's PNG text chunks and EXR
# attributes, read back with tools other than ours (GDAL's PNG driver,
# OpenEXR's exrheader, jq), against the command line and the weather state.
. "$TOP/tests/tools/lib.sh"
plan 5
CR="$BIN/cloudrender"
FAST="--size 48x27 --quality low --noise-size 16 -q"
CAM="--camera 46.9,7.5,1234 --look 123,4.5 --fov 55"
printf '{"schema":"cloudwx/1","time_utc":"2021-06-14T15:20:00Z","site":{"name":"Bern","lat_deg":46.95,"lon_deg":7.44,"alt_m":540},"layers":[{"genus":"stratocumulus","coverage":0.7,"base_m":1300,"top_m":1900},{"genus":"cirrus","coverage":0.25,"base_m":9000,"top_m":9600}],"precipitation_mm_h":2.5,"wind":{"speed_m_s":7.5,"from_deg":190},"visibility_m":12000,"fog_probability":0.1,"temperature_c":14.25}\n' >"$T/wx.json"
version=$("$CR" --version | awk '{ print $NF }')

# png_meta FILE KEY: the text chunk KEY as GDAL's PNG driver reads it
png_meta() { gdalinfo -json "$1" 2>/dev/null | jq -r --arg k "$2" '.metadata[""][$k] // empty'; }
# frame_check JSON: the description against the command line and the state
frame_check() {
	printf '%s\n' "$1" | jq -e --arg v "$version" '
		.program == "cloudrender" and .version == $v and
		.time_utc == "2021-06-14T15:20:00Z" and .size == [48, 27] and
		.camera.lat_deg == 46.9 and .camera.lon_deg == 7.5 and .camera.alt_m == 1234 and
		.camera.azimuth_deg == 123 and .camera.elevation_deg == 4.5 and
		.camera.fov_deg == 55 and .camera.projection == "perspective" and
		.quality.preset == "low" and .quality.steps == 17 and .quality.light_steps == 3 and
		.quality.integrator == "march" and .quality.seed == 9 and
		.quality.deck_lattice == "diffusion" and
		.weather.site.name == "Bern" and .weather.site.lat_deg == 46.95 and
		(.weather.layers | length) == 2 and
		.weather.layers[0] == {"genus":"stratocumulus","coverage":0.7,"base_m":1300,"top_m":1900} and
		.weather.layers[1] == {"genus":"cirrus","coverage":0.25,"base_m":9000,"top_m":9600} and
		.weather.precipitation_mm_h == 2.5 and .weather.wind == {"speed_m_s":7.5,"from_deg":190} and
		.weather.visibility_m == 12000 and .weather.fog_probability == 0.1 and
		.weather.temperature_c == 14.25' >/dev/null
}
SET="--wx $T/wx.json $CAM --steps 17 --light-steps 3 --seed 9"

begin metadata_png_text_chunks_say_what_the_frame_shows
# shellcheck disable=SC2086
run "$CR" $SET $FAST -o "$T/f.png" -o "$T/f16.png" -of PNG -o "$T/g.dat"
expect_rc 0
[ "$(png_meta "$T/f.png" Software)" = "cloudrender (cloudscape) $version" ] ||
	bad "Software: '$(png_meta "$T/f.png" Software)'"
json=$(png_meta "$T/f.png" cloudscape)
[ -n "$json" ] || bad "no cloudscape text chunk: $(gdalinfo "$T/f.png" 2>&1 | head -c 300)"
frame_check "$json" || bad "the description does not match: $json"
png_meta "$T/f.png" Description | grep -q '^2021-06-14 15:20 UTC  Bern' ||
	bad "Description: $(png_meta "$T/f.png" Description)"
png_meta "$T/f.png" Description | grep -q 'stratocumulus 70% 1300-1900 m, cirrus 25% 9000-9600 m' ||
	bad "Description lacks the layers"
png_meta "$T/f.png" Description | grep -q 'rain 2.5 mm/h, wind 7.5 m/s from 190 deg, visibility 12 km, fog 10%, 14.2 C' ||
	bad "Description lacks the weather: $(png_meta "$T/f.png" Description)"
for f in f16.png g.dat; do
	frame_check "$(png_meta "$T/$f" cloudscape)" || bad "$f: no or another description"
done
end

begin metadata_exr_attributes_say_what_the_frame_shows
# shellcheck disable=SC2086
run "$CR" $SET $FAST -o "$T/f.exr"
expect_rc 0
exrheader "$T/f.exr" >"$T/h" 2>&1 || bad "exrheader cannot read it: $(head -c 300 "$T/h")"
grep -q '^capDate (type string): "2021:06:14 15:20:00"' "$T/h" || bad "capDate: $(grep capDate "$T/h")"
grep -q '^utcOffset (type float): 0$' "$T/h" || bad "utcOffset: $(grep utcOffset "$T/h")"
grep -q '^latitude (type float): 46.9$' "$T/h" || bad "latitude: $(grep latitude "$T/h")"
grep -q '^longitude (type float): 7.5$' "$T/h" || bad "longitude: $(grep longitude "$T/h")"
grep -q '^altitude (type float): 1234$' "$T/h" || bad "altitude: $(grep altitude "$T/h")"
grep -q "^cloudscapeSoftware (type string): \"cloudrender (cloudscape) $version\"" "$T/h" ||
	bad "cloudscapeSoftware: $(grep cloudscapeSoftware "$T/h")"
grep -q '^comments (type string): "2021-06-14 15:20 UTC  Bern' "$T/h" || bad "comments: $(grep -A2 comments "$T/h")"
json=$(sed -n 's/^cloudscapeFrame (type string): "\(.*\)"$/\1/p' "$T/h")
frame_check "$json" || bad "the description does not match: $json"
end

begin metadata_records_the_resolved_quality_and_the_view
run "$CR" --view gurten --quality medium $FAST --quality high --no-ambient --max-steps 500 -o "$T/v.png"
expect_rc 0
png_meta "$T/v.png" cloudscape | jq -e '.camera.view == "gurten" and .quality.preset == "high" and
	.quality.ambient == false and .quality.max_steps == 500 and .quality.haze == true' >/dev/null ||
	bad "view or quality not recorded: $(png_meta "$T/v.png" cloudscape | jq -c '.camera, .quality')"
run "$CR" --integrator reference --spp 2 --max-bounces 3 --no-haze $FAST -o "$T/r.png"
expect_rc 0
png_meta "$T/r.png" cloudscape | jq -e '.quality.integrator == "reference" and .quality.spp == 2 and
	.quality.max_bounces == 3 and .quality.haze == false' >/dev/null ||
	bad "reference settings not recorded: $(png_meta "$T/r.png" cloudscape | jq -c .quality)"
end

begin metadata_is_the_same_for_the_same_inputs
# shellcheck disable=SC2086
run "$CR" $SET $FAST -t 1 -o "$T/a.png" -o "$T/a.exr"; expect_rc 0
# shellcheck disable=SC2086
run "$CR" $SET $FAST -t 3 -o "$T/b.png" -o "$T/b.exr"; expect_rc 0
cmp -s "$T/a.png" "$T/b.png" || bad "two runs wrote different PNGs"
cmp -s "$T/a.exr" "$T/b.exr" || bad "two runs wrote different EXRs"
end

begin metadata_time_now_is_the_clock
before=$(date -u +%s)
run "$CR" --time now $FAST -o "$T/now.png"
expect_rc 0
after=$(date -u +%s)
t=$(png_meta "$T/now.png" cloudscape | jq -r .time_utc)
s=$(date -u -d "$t" +%s 2>/dev/null || echo 0)
[ "$s" -ge $((before - 1)) ] && [ "$s" -le "$after" ] || bad "--time now rendered $t, the clock said $before..$after"
run "$CR" --time then $FAST -o "$T/then.png"
expect_rc 2; expect_err "--time:"; expect_no_file "$T/then.png"
end
