# The picture cloudrender makes, read back: the EXR's channels along rays
# whose answer geometry gives, the far site's weather where it is, and the
# direction of what options and weather change.
. "$TOP/tests/tools/lib.sh"
plan 5
CR="$BIN/cloudrender"
PX="$HELPERS/exrpixel"
Q="--quality low --noise-size 16 -q"
# wx FILE LAYERS [EXTRA]: Bern at 540 m, 2021-06-14 15:00 UTC
wx() {
	printf '{"schema":"cloudwx/1","time_utc":"2021-06-14T15:00:00Z","site":{"name":"Bern","lat_deg":46.95,"lon_deg":7.44,"alt_m":540},"layers":[%s]%s}\n' "$2" "${3:-}" >"$1"
}
NS='{"genus":"nimbostratus","coverage":1,"base_m":1000,"top_m":4000}'
# near A B TOL: |A - B| <= TOL
near() { awk -v a="$1" -v b="$2" -v t="$3" 'BEGIN { d = a - b; exit !(a != "" && (d < 0 ? -d : d) <= t) }'; }
gt() { awk -v a="$1" -v b="$2" 'BEGIN { exit !(a != "" && b != "" && a > b) }'; }
# at FILE X Y CHANNEL...: the values (the second line of exrpixel)
at() { "$PX" "$@" | sed -n 2p; }
mean() { "$PX" "$1" mean "$2" | sed -n 2p; }

# 33x19: pixel (16, 9) is the centre ray, which points where --look says
begin picture_exr_alpha_and_depth_along_known_rays
wx "$T/clear.json" ""
run "$CR" --wx "$T/clear.json" --camera 46.95,7.44,542 --look 0,90 --size 33x19 $Q -o "$T/up.exr"
expect_rc 0
set -- $(at "$T/up.exr" 16 9 A Z)
[ "$1" = 0 ] || bad "clear sky overhead has alpha $1, expected 0"
gt "$2" 1e9 || bad "clear sky overhead has depth $2, expected 1e10 (nothing hit)"
wx "$T/ns.json" "$NS"
run "$CR" --wx "$T/ns.json" --camera 46.95,7.44,542 --look 0,90 --size 33x19 $Q -o "$T/ns.exr"
expect_rc 0
set -- $(at "$T/ns.exr" 16 9 A Z)
gt "$1" 0.95 || bad "a 3 km nimbostratus overhead has alpha $1, expected > 0.95 (the march stops at the quality's least transmittance)"
# the base is 1000 - 542 = 458 m straight up
near "$2" 458 15 || bad "the depth to a base 458 m overhead is $2"
# looking 30 deg down from 1000 m over flat ground: 1000 / sin 30 = 2000 m
run "$CR" --wx "$T/clear.json" --camera 46.95,7.44,1540 --look 0,-30 --size 33x19 $Q -o "$T/down.exr"
expect_rc 0
set -- $(at "$T/down.exr" 16 9 A Z)
[ "$1" = 0 ] || bad "the ground under a clear sky has alpha $1"
near "$2" 2000 20 || bad "the ground 2000 m along the ray is at depth $2"
end

# A far site 30 km east (Bern's longitude + 0.394 deg) under nimbostratus,
# Bern itself clear: overhead at the far site is cloud, overhead at Bern
# is not; and the other way round.
begin picture_far_site_weather_is_drawn_at_the_far_site
FAR='"far":[{"site":{"name":"East","lat_deg":46.95,"lon_deg":7.834,"alt_m":540},"layers":[%s]}]'
wx "$T/far.json" "" ",$(printf "$FAR" "$NS")"
wx "$T/farclear.json" "$NS" ",$(printf "$FAR" "")"
for f in far farclear; do
	for c in 7.44 7.834; do
		run "$CR" --wx "$T/$f.json" --camera 46.95,$c,542 --look 0,90 --fov 20 --size 9x9 $Q -o "$T/$f-$c.exr"
		expect_rc 0
	done
done
a=$(mean "$T/far-7.44.exr" A); b=$(mean "$T/far-7.834.exr" A)
near "$a" 0 0.01 || bad "clear Bern with an overcast far site: alpha $a overhead at Bern"
gt "$b" 0.95 || bad "overcast far site: alpha $b overhead there"
a=$(mean "$T/farclear-7.44.exr" A); b=$(mean "$T/farclear-7.834.exr" A)
gt "$a" 0.95 || bad "overcast Bern: alpha $a overhead"
near "$b" 0 0.01 || bad "clear far site: alpha $b overhead there"
end

# The sun where the time puts it: at 06:00 UTC (08:00 local) the eastern
# sky 10 deg up is brighter than the western, at 18:00 UTC the other way.
begin picture_the_sun_is_east_in_the_morning_and_west_in_the_evening
wx "$T/clear.json" ""
for t in 06 18; do
	for az in 90 270; do
		run "$CR" --wx "$T/clear.json" --time 2021-06-14T$t:00Z --look $az,10 --fov 60 --size 9x9 $Q \
			-o "$T/s$t-$az.exr"
		expect_rc 0
	done
done
gt "$(mean "$T/s06-90.exr" G)" "$(mean "$T/s06-270.exr" G)" || bad "at 06Z the east is not brighter"
gt "$(mean "$T/s18-270.exr" G)" "$(mean "$T/s18-90.exr" G)" || bad "at 18Z the west is not brighter"
end

# Haze: the ground 19 km away (1.5 deg down from 500 m up) against the sky
# 5 deg up: its contrast falls with the visibility (Koschmieder: about
# exp(-3.912 d / V) of it is left).
begin picture_more_haze_means_less_contrast
for v in 60000 20000 8000; do
	wx "$T/v$v.json" "" ",\"visibility_m\":$v"
	run "$CR" --wx "$T/v$v.json" --camera 46.95,7.44,1040 --look 160,-1.5 --fov 1 --size 3x3 $Q -o "$T/g$v.exr"
	expect_rc 0
	run "$CR" --wx "$T/v$v.json" --camera 46.95,7.44,1040 --look 160,5 --fov 1 --size 3x3 $Q -o "$T/k$v.exr"
	expect_rc 0
done
c() { awk -v g="$(mean "$T/g$1.exr" G)" -v k="$(mean "$T/k$1.exr" G)" 'BEGIN { d = g - k; printf "%.4f", (d < 0 ? -d : d) / k }'; }
c60=$(c 60000); c20=$(c 20000); c8=$(c 8000)
gt "$c60" "$c20" && gt "$c20" "$c8" || bad "contrast at V = 60, 20, 8 km: $c60, $c20, $c8 (should fall)"
gt "$c8" 0.001 || bad "no contrast left at V = 8 km: $c8"
end

# What the options must change, in the direction they must: from under a
# stratocumulus of 90 % cover (every pixel cloud), no sky light makes the
# cloud darker, fewer multiple-scattering octaves change it by less than
# 1 % (its light fields hold its multiple scattering; the octaves add only
# what the beam brings in through a nearer side of a cell, so that one
# octave is a little darker: measured -0.06 %), and under one of 50 %
# cover (lit by the octaves) they make it darker; two stops of exposure
# make the PNG brighter; looking down shows the ground (finite depth), up
# only sky.
begin picture_options_push_the_picture_the_right_way
wx "$T/sc.json" '{"genus":"stratocumulus","coverage":0.9,"base_m":1200,"top_m":1800}'
V="--wx $T/sc.json --camera 46.95,7.44,542 --look 0,60 --fov 40 --size 17x9 $Q"
run "$CR" $V -o "$T/base.exr" -o "$T/base.png"; expect_rc 0
run "$CR" $V --ms-octaves 1 -o "$T/ms1.exr"; expect_rc 0
run "$CR" $V --no-ambient -o "$T/noamb.exr"; expect_rc 0
run "$CR" $V --exposure 2 -o "$T/ev2.png"; expect_rc 0
b=$(mean "$T/base.exr" G)
gt "$(mean "$T/base.exr" A)" 0.9 || bad "the overcast view is not all cloud"
m1=$(mean "$T/ms1.exr" G)
near "$m1" "$b" "$(awk -v b="$b" 'BEGIN { print 0.01 * b }')" && gt "$b" "$m1" ||
	bad "one octave changed the light of a 90 % cover by 1 % or more, or did not darken it ($m1, $b)"
wx "$T/sc50.json" '{"genus":"stratocumulus","coverage":0.5,"base_m":1200,"top_m":1800}'
V50="--wx $T/sc50.json --camera 46.95,7.44,542 --look 0,60 --fov 40 --size 17x9 $Q"
run "$CR" $V50 -o "$T/b50.exr"; expect_rc 0
run "$CR" $V50 --ms-octaves 1 -o "$T/ms50.exr"; expect_rc 0
b50=$(mean "$T/b50.exr" G)
gt "$b50" "$(mean "$T/ms50.exr" G)" || bad "one octave is not darker than the default under 50 % cover ($b50)"
# between 50 and 70 % cover the light fields take a growing share: at
# 60 % the octaves still count, and the light does not jump as the cover
# passes 50 % (the two models differ by up to 30 % in a layer of middle
# cover: a switch at 50 % would show here)
for c in 0.51 0.6; do
	wx "$T/sc$c.json" "{\"genus\":\"stratocumulus\",\"coverage\":$c,\"base_m\":1200,\"top_m\":1800}"
	run "$CR" --wx "$T/sc$c.json" --camera 46.95,7.44,542 --look 0,60 --fov 40 --size 17x9 $Q -o "$T/c$c.exr"; expect_rc 0
done
run "$CR" --wx "$T/sc0.6.json" --camera 46.95,7.44,542 --look 0,60 --fov 40 --size 17x9 $Q --ms-octaves 1 -o "$T/m0.6.exr"; expect_rc 0
gt "$(mean "$T/c0.6.exr" G)" "$(mean "$T/m0.6.exr" G)" || bad "one octave is not darker under 60 % cover"
jump=$(awk -v a="$b50" -v b="$(mean "$T/c0.51.exr" G)" 'BEGIN { d = (b - a) / a; printf "%.4f", d < 0 ? -d : d }')
gt 0.03 "$jump" || bad "the light jumps by $jump from 50 to 51 % cover"
gt "$b" "$(mean "$T/noamb.exr" G)" || bad "no sky light is not darker than the default ($b)"
pngmean() { pngtopnm "$1" | pnmtoplainpnm | awk 'NR > 3 { for (i = 1; i <= NF; i++) { s += $i; n++ } } END { print s / n }'; }
gt "$(pngmean "$T/ev2.png")" "$(pngmean "$T/base.png")" || bad "--exposure 2 is not brighter"
wx "$T/clear.json" ""
run "$CR" --wx "$T/clear.json" --look 160,30 --fov 40 --size 17x9 $Q -o "$T/upz.exr"; expect_rc 0
run "$CR" --wx "$T/clear.json" --look 160,-30 --fov 40 --size 17x9 $Q -o "$T/downz.exr"; expect_rc 0
gt "$(mean "$T/upz.exr" Z)" 9e9 || bad "looking 30 deg up met something"
gt 1e5 "$(mean "$T/downz.exr" Z)" || bad "looking 30 deg down from 2 m did not meet the ground nearby"
end
