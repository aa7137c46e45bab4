# cloudrender as a user runs it.
. "$TOP/tests/tools/lib.sh"
plan 17
CR="$BIN/cloudrender"
NB="$BIN/noisebake"
FAST="--size 48x27 --quality low --noise-size 16 -q"

wx_json() { # genus coverage base top [extra top-level members]
	printf '{"schema":"cloudwx/1","time_utc":"2021-06-14T15:00:00Z","site":{"name":"Bern","lat_deg":46.95,"lon_deg":7.44,"alt_m":540},"layers":[{"genus":"%s","coverage":%s,"base_m":%s,"top_m":%s}]%s}\n' "$@"
}
png_size() { od -An -tu1 -j16 -N8 "$1" | tr -s ' '; }

begin cloudrender_default_scene_renders_png_and_exr
run "$CR" -o "$T/sky.png" -o "$T/sky.exr" --size 64x36 --noise-size 16 -q
expect_rc 0; expect_file "$T/sky.png"; expect_file "$T/sky.exr"
[ "$(png_size "$T/sky.png")" = " 0 0 0 64 0 0 0 36" ] || bad "PNG is not 64x36"
head -c 4 "$T/sky.exr" | od -An -tx1 | grep -q '76 2f 31 01' || bad "EXR magic missing"
end

begin cloudrender_exr_holds_rgba_and_depth
run "$CR" -o "$T/d.exr" $FAST
expect_rc 0
# each channel read back (a PNG or a missing channel fails the reader)
"$HELPERS/exrpixel" "$T/d.exr" 0 0 A B G R Z >"$T/px" 2>&1 || bad "channels not read back: $(cat "$T/px")"
[ "$(sed -n 1p "$T/px")" = 48x27 ] || bad "EXR size $(sed -n 1p "$T/px"), expected 48x27"
[ "$(sed -n 2p "$T/px" | wc -w)" -eq 5 ] || bad "not five values: $(sed -n 2p "$T/px")"
"$HELPERS/exrpixel" "$T/d.exr" 0 0 Q >/dev/null 2>&1 && bad "a channel Q read back from an EXR without one"
grep -qa 'cloudscapeTimeUTC' "$T/d.exr" || bad "no time attribute"
end

# The sun's disc (about 1.6 million kcd/m^2 at 18:20 UTC in June, 6 deg up)
# is past the largest half: a half EXR holds 65504 there, not inf, and a
# float EXR its radiance
begin cloudrender_half_exr_holds_the_sun_finite
printf '{"schema":"cloudwx/1","time_utc":"2021-06-14T18:20:00Z","site":{"name":"Bern","lat_deg":46.95,"lon_deg":7.44,"alt_m":540},"layers":[],"visibility_m":40000}\n' >"$T/sun.json"
for f in half float; do
	opt=""; [ $f = float ] && opt=--float
	# shellcheck disable=SC2086
	run "$CR" --wx "$T/sun.json" --look 295,6 --fov 60 --size 96x54 --noise-size 16 -q $opt \
		-o "$T/sun-$f.exr"; expect_rc 0
	"$HELPERS/exrpixels" "$T/sun-$f.exr" R G B | sed 1d | tr ' ' '\n' >"$T/sun-$f.txt" ||
		bad "cannot read $T/sun-$f.exr"
done
grep -qiv '^[-+0-9a-fx.p]*$' "$T/sun-half.txt" && bad "the half EXR holds $(grep -iv '^[-+0-9a-fx.p]*$' "$T/sun-half.txt" | sort -u | tr '\n' ' ')"
grep -qx '0x1.ffcp+15' "$T/sun-half.txt" || bad "no pixel of the half EXR at 65504 (the sun's disc)"
top=$(sort -g "$T/sun-float.txt" | tail -n 1) # (sort -g reads C99 hexadecimal floats)
[ "$(printf '1e5\n%s\n' "$top" | sort -g | tail -n 1)" = "$top" ] && [ "$top" != 1e5 ] ||
	bad "the float EXR's brightest pixel $top kcd/m^2, expected above 1e5"
end

begin cloudrender_reads_weather_from_stdin_and_file
wx_json cumulus 0.6 1500 2700 "" >"$T/wx.json"
run "$CR" --wx "$T/wx.json" -o "$T/a.png" $FAST; expect_rc 0
"$CR" --wx - -o "$T/b.png" $FAST <"$T/wx.json" 2>"$T/err"; rc=$?
expect_rc 0
cmp -s "$T/a.png" "$T/b.png" || bad "stdin and file renders differ"
end

begin cloudrender_output_is_identical_for_any_thread_count
run "$CR" -o "$T/t1.png" -t 1 $FAST; expect_rc 0
run "$CR" -o "$T/t3.png" -t 3 $FAST; expect_rc 0
cmp -s "$T/t1.png" "$T/t3.png" || bad "1 and 3 threads differ"
end

begin cloudrender_clear_sky_has_no_clouds_and_costs_nothing
printf '{"schema":"cloudwx/1","time_utc":"2021-06-14T15:00:00Z","site":{"lat_deg":46.95,"lon_deg":7.44,"alt_m":540},"layers":[]}\n' >"$T/clear.json"
run "$CR" --wx "$T/clear.json" -o "$T/c.png" --stats $FAST
expect_rc 0
grep -q '"density_samples":0,' "$T/err" || bad "a clear sky sampled density"
grep -q '"effects":\["sun","sky","ground","haze"\]' "$T/err" || bad "effects: $(grep -o '"effects":[^]]*]' "$T/err")"
end

begin cloudrender_rain_is_simulated_only_when_it_rains
wx_json nimbostratus 1.0 900 4000 ',"precipitation_mm_h":3' >"$T/rain.json"
run "$CR" --wx "$T/rain.json" -o "$T/r.png" --stats $FAST; expect_rc 0
grep -q '"rain"' "$T/err" || bad "no rain effect when raining"
wx_json nimbostratus 1.0 900 4000 '' >"$T/dry.json"
run "$CR" --wx "$T/dry.json" -o "$T/r.png" --stats $FAST; expect_rc 0
grep -q '"rain"' "$T/err" && bad "rain simulated without precipitation"
end

begin cloudrender_stats_report_phases_and_counts
run "$CR" -o "$T/s.png" --stats $FAST
expect_rc 0
for k in '"wall_s":{"noise":' '"render":' '"density_samples":' '"light_samples":' \
	'"rays_terminated_early":' '"layers":[{"genus":"cumulus"' '"effects":['; do
	grep -qF "$k" "$T/err" || bad "stats lack $k"
done
end

begin cloudrender_views_and_explicit_camera
run "$CR" --list-views; expect_rc 0; expect_out gurten; expect_out bantiger
run "$CR" --view gurten -o "$T/g.png" $FAST; expect_rc 0
run "$CR" --view bantiger -o "$T/b.png" $FAST; expect_rc 0
same_pixels "$T/g.png" "$T/b.png" && bad "two views gave the same image"
run "$CR" --camera 46.95,7.44,3000 --look 90,-10 --fov 40 -o "$T/c.png" $FAST; expect_rc 0
# the centre ray of that camera under a clear sky meets the ground (a sphere
# of radius R + 540 m) where geometry says: R = 6371 km, 2460 m up, 10 deg down
printf '{"schema":"cloudwx/1","time_utc":"2021-06-14T15:00:00Z","site":{"lat_deg":46.95,"lon_deg":7.44,"alt_m":540},"layers":[]}\n' >"$T/clear0.json"
run "$CR" --wx "$T/clear0.json" --camera 46.95,7.44,3000 --look 90,-10 --fov 40 --size 33x19 \
	--quality low --noise-size 16 -q -o "$T/c.exr"
expect_rc 0
z=$("$HELPERS/exrpixel" "$T/c.exr" 16 9 Z | sed -n 2p)
awk -v z="$z" 'BEGIN { R = 6371000; o = R + 3000; g = R + 540; s = sin(10 * 3.14159265358979 / 180)
	t = o * s - sqrt(o * o * s * s - (o * o - g * g)); exit !(z != "" && (z - t < 0 ? t - z : z - t) < 0.01 * t) }' ||
	bad "the ground along the explicit camera's centre ray is at $z m"
run "$CR" --time 2021-06-14T21:30Z -o "$T/n.png" --stats $FAST; expect_rc 0
grep -q '"effects":\["sky"' "$T/err" || bad "night still has the sun"
end

begin cloudrender_options_change_the_picture
run "$CR" -o "$T/base.png" $FAST; expect_rc 0
for o in "--exposure 2" "--steps 5" "--light-steps 1" "--ms-octaves 1" "--no-ambient" \
	"--no-jitter" "--seed 7" "--time 2021-06-14T08:00Z" "--fov 30" "--look 0,20" \
	"--quality medium"; do
	# shellcheck disable=SC2086
	run "$CR" -o "$T/o.png" $FAST $o
	expect_rc 0
	same_pixels "$T/base.png" "$T/o.png" && bad "$o did not change the image"
done
end

begin cloudrender_reads_a_baked_noise_volume
run "$NB" -s 16 -o "$T/n.exr" -q; expect_rc 0
run "$CR" --noise "$T/n.exr" -o "$T/n.png" $FAST; expect_rc 0
# the volume is the clouds' shape: the same file draws the same sky, another
# seed another one
run "$CR" --noise "$T/n.exr" -o "$T/n2.png" $FAST; expect_rc 0
cmp -s "$T/n.png" "$T/n2.png" || bad "the same noise file drew two skies"
run "$NB" -s 16 --seed 5 -o "$T/n5.exr" -q; expect_rc 0
run "$CR" --noise "$T/n5.exr" -o "$T/n5.png" $FAST; expect_rc 0
cmp -s "$T/n.png" "$T/n5.png" && bad "another noise seed drew the same sky"
end

begin cloudrender_bad_input_is_a_clear_error_and_leaves_nothing
echo old >"$T/keep.png"
check_bad() { # expected-status message args...
	want=$1; msg=$2; shift 2
	run "$CR" -o "$T/keep.png" -o "$T/new.exr" "$@"
	expect_rc "$want"; expect_err "$msg"
	[ "$(cat "$T/keep.png")" = old ] || bad "'$*' clobbered the output"
	expect_no_file "$T/new.exr"
	[ "$(wc -l <"$T/err")" -le 2 ] || bad "'$*' printed more than a line or two"
}
printf '{"schema":"cloudwx/1",' >"$T/trunc.json"
check_bad 1 "cloudrender: $T/trunc.json: malformed JSON" --wx "$T/trunc.json" $FAST
wx_json cumulous 0.5 1500 2700 "" >"$T/genus.json"
check_bad 1 'unknown genus "cumulous"' --wx "$T/genus.json" $FAST
wx_json cumulus 1.5 1500 2700 "" >"$T/cov.json"
check_bad 1 "layers[0].coverage: 1.5 is outside 0..1" --wx "$T/cov.json" $FAST
check_bad 1 "cloudrender: cannot open $T/none.json" --wx "$T/none.json" $FAST
check_bad 1 "cannot open $T/none.exr" --noise "$T/none.exr" $FAST
printf 'not an exr' >"$T/bad.exr"
check_bad 1 "not a readable OpenEXR file" --noise "$T/bad.exr" $FAST
check_bad 2 "--size: 0 is out of range" --size 0x10 -q
check_bad 2 "--size: expected WxH" --size 100 -q
check_bad 2 "image size 16384x16384 is too large: it would need about 13.2 GB" --size 16384x16384 -q
check_bad 2 "--view: unknown view 'nowhere'" --view nowhere -q
check_bad 2 "--quality: unknown quality 'best'" --quality best -q
check_bad 2 "--time: '2021-06-14 15:00' is not an ISO 8601 UTC time" --time "2021-06-14 15:00" -q
check_bad 2 "below the ground" --camera 46.95,7.44,100 $FAST
check_bad 2 "--fov: 0 is out of range" --fov 0 -q
check_bad 2 "--look: expected two comma-separated numbers" --look 90 -q
run "$CR" -o "$T/x.bmp" -q; expect_rc 2; expect_err "must end in .png, .exr, .tif, .tiff, .jpg or .jpeg"
run "$CR" -q; expect_rc 2; expect_err "no output"
run "$CR" --bogus; expect_rc 2; expect_err "Try 'cloudrender --help'"
end

begin cloudrender_writes_png_to_stdout
run "$CR" -o - $FAST; expect_rc 0
head -c 8 "$T/out" | od -An -tx1 | grep -q '89 50 4e 47' || bad "stdout is not a PNG"
end

begin cloudrender_help_matches_man_page
run "$CR" --help; expect_rc 0; expect_out "Usage: cloudrender"
for o in $(grep -o -- '--[a-z][a-z-]*' "$T/out" | sort -u); do
	grep -q -- "Fl ${o#-}" "$TOP/man/cloudrender.1" || bad "man page lacks $o"
done
for o in $(grep -o 'Fl -[a-z][a-z-]*' "$TOP/man/cloudrender.1" | sed 's/Fl -/--/' | sort -u); do
	grep -q -- "$o" "$T/out" || bad "--help lacks $o"
done
run "$CR" --version; expect_rc 0; expect_out "cloudrender (cloudscape)"
end

begin cloudrender_renders_terrain_and_refuses_a_camera_inside_it
TP="$BIN/terrainprep"
if "$TOP/scripts/make-bern-dem" -r 400 "$T/dem.tif" >/dev/null 2>&1 &&
	"$TP" -q "$T/dem.tif" -o "$T/bern.exr" 2>"$T/err"; then
	run "$CR" --terrain "$T/bern.exr" --view gurten -o "$T/g.png" --stats $FAST
	expect_rc 0
	grep -q '"terrain"' "$T/err" || bad "no terrain effect"
	grep -q '"terrain_cells":0,' "$T/err" && bad "no terrain cell was visited"
	run "$CR" --view gurten -o "$T/flat.png" $FAST
	expect_rc 0
	same_pixels "$T/g.png" "$T/flat.png" && bad "the terrain changed nothing"
	# inside the Gurten (858 m) at 700 m
	run "$CR" --terrain "$T/bern.exr" --camera 46.91722,7.44361,700 -o "$T/in.png" $FAST
	expect_rc 2; expect_err "below the terrain"; expect_no_file "$T/in.png"
	"$NB" -s 8 -q --preview "$T/drape.png"
	run "$CR" --terrain "$T/bern.exr" --terrain-color "$T/drape.png" --view gurten -o "$T/c.png" $FAST
	expect_rc 0
	cmp -s "$T/g.png" "$T/c.png" && bad "--terrain-color changed nothing"
	run "$CR" --terrain-color "$T/drape.png" -o "$T/c.png" $FAST
	expect_rc 2; expect_err "--terrain-color needs --terrain"
	rm "$T/bern.json"
	run "$CR" --terrain "$T/bern.exr" -o "$T/x.png" $FAST
	expect_rc 1; expect_err "bern.json"; expect_no_file "$T/x.png"
else
	bad "could not make a test terrain: $(head -c 300 "$T/err")"
fi
end

begin cloudrender_auto_exposure_shows_the_night
run "$CR" --time 2021-06-14T21:30Z -o "$T/night0.png" --stats $FAST
expect_rc 0
grep -q '"exposure_ev":0.000' "$T/err" || bad "fixed exposure is not 0"
run "$CR" --time 2021-06-14T21:30Z --exposure auto -o "$T/nightA.png" --stats $FAST
expect_rc 0
ev=$(sed -n 's/.*"exposure_ev":\([0-9.-]*\).*/\1/p' "$T/err")
awk -v e="$ev" 'BEGIN { exit !(e > 15) }' || bad "auto exposure at night is $ev stops, expected > 15"
run "$CR" --exposure auto -o "$T/dayA.png" --stats $FAST
ev=$(sed -n 's/.*"exposure_ev":\([0-9.-]*\).*/\1/p' "$T/err")
awk -v e="$ev" 'BEGIN { exit !(e > -3 && e < 3) }' || bad "auto exposure by day is $ev stops, expected near 0"
run "$CR" --exposure bright -o "$T/x.png" $FAST; expect_rc 2; expect_err "--exposure: 'bright' is not a number"
end

begin cloudrender_warns_when_the_camera_is_far_from_the_weather
run "$CR" --camera 40.0,-3.7,700 -o "$T/far.png" --size 32x18 --noise-size 16
expect_rc 0
expect_err "cloudrender: warning: the camera is 1"
expect_err "km from the weather site (Bern)"
run "$CR" -o "$T/near.png" --size 32x18 --noise-size 16
[ -s "$T/err" ] && bad "a warning for the default camera: $(cat "$T/err")"
end
