# Cameras that are easy to place: --camera-agl, --look-at, --views files
# and view names in any case.  The look-at directions are checked against
# the great-circle initial bearing and the elevation over a curved Earth,
# computed here with python3 from their textbook formulas; the heights
# against the elevation models' own values (gdal_create, gdallocationinfo).
. "$TOP/tests/tools/lib.sh"
plan 8
CR="$BIN/cloudrender"
TP="$BIN/terrainprep"
FAST="--size 32x18 --quality low --noise-size 16 -q"
PY=python3

# camera FIELD: from cloudrender -v's camera line in $T/err: lat lon alt az el
camera() {
	sed -n 's/.*camera \([-0-9.]*\), \([-0-9.]*\), \([-0-9.]*\) m, looking azimuth \([-0-9.]*\) deg, elevation \([-0-9.]*\) deg.*/\1 \2 \3 \4 \5/p' "$T/err"
}
near() { awk -v a="$1" -v b="$2" -v t="$3" 'BEGIN { d = a - b; if (d < 0) d = -d; exit !(d <= t) }'; }

begin cloudrender_look_at_matches_the_great_circle_bearing_and_curved_elevation
if command -v $PY >/dev/null 2>&1; then
	# from the Gurten tower: Solothurn (30 km), a summit 200 km west-north-west
	# (the Earth's curve sinks it by about 0.9 deg), a point 1 km east and 500 m up
	for tgt in 47.20791,7.53714,432 47.5,4.9,3000 46.91722,7.45676,1383 46.0,7.44361,4000; do
		run "$CR" --camera 46.91722,7.44361,883 --look-at "$tgt" -v -o "$T/l.png" $FAST
		expect_rc 0
		set -- $(camera)
		want=$($PY -c '
import math, sys
R = 6371000.0
la1, lo1, h1 = 46.91722, 7.44361, 883.0
la2, lo2, h2 = map(float, sys.argv[1].split(","))
p1, p2, dl = math.radians(la1), math.radians(la2), math.radians(lo2 - lo1)
# initial bearing of the great circle (e.g. Williams, Aviation Formulary)
b = math.degrees(math.atan2(math.sin(dl) * math.cos(p2),
    math.cos(p1) * math.sin(p2) - math.sin(p1) * math.cos(p2) * math.cos(dl))) % 360
# central angle (haversine), then the elevation in the plane of the two
# radii: the target at (r2 sin c, r2 cos c - r1) from the eye
hv = math.sin((p2 - p1) / 2) ** 2 + math.cos(p1) * math.cos(p2) * math.sin(dl / 2) ** 2
c = 2 * math.asin(math.sqrt(hv))
r1, r2 = R + h1, R + h2
e = math.degrees(math.atan2(r2 * math.cos(c) - r1, r2 * math.sin(c)))
print("%.4f %.4f" % (b, e))' "$tgt")
		set -- "$4" "$5" $want
		near "$1" "$3" 0.06 || bad "$tgt: azimuth $1 deg, the great circle's bearing $3"
		near "$2" "$4" 0.06 || bad "$tgt: elevation $2 deg, expected $4"
	done
else
	bad "python3 is missing (scripts/deps installs it)"
fi
end

begin cloudrender_look_at_excludes_look_and_refuses_bad_points
run "$CR" --look 10,5 --look-at 47.2,7.5,432 -o "$T/x.png" $FAST
expect_rc 2; expect_err "--look and --look-at exclude each other"; expect_no_file "$T/x.png"
run "$CR" --look-at 47.2,7.5 -o "$T/x.png" $FAST
expect_rc 2; expect_err "--look-at: expected LAT,LON,ALT_M"
run "$CR" --look-at 95,7.5,400 -o "$T/x.png" $FAST
expect_rc 2; expect_err "--look-at"
# the point the camera stands on has no direction
run "$CR" --camera 46.9,7.4,600 --look-at 46.9,7.4,600 -o "$T/x.png" $FAST
expect_rc 2; expect_err "is where the camera is"; expect_no_file "$T/x.png"
end

begin cloudrender_camera_agl_stands_above_the_terrain_or_the_ground
# no terrain: the weather site's ground (the built-in Bern, 540 m)
run "$CR" --camera 46.95,7.44 --camera-agl 100 -v -o "$T/a.png" $FAST
expect_rc 0
set -- $(camera); [ "${3:-}" = 640 ] || bad "without terrain at ${3:-?} m, expected 540 + 100"
run "$CR" --camera-agl 30 -v -o "$T/a.png" $FAST
expect_rc 0
set -- $(camera); [ "${3:-}" = 570 ] || bad "the default camera at ${3:-?} m, expected 540 + 30"
# a flat 700 m terrain made by gdal_create
if gdal_create -q -of GTiff -outsize 50 50 -bands 1 -burn 700 -a_srs EPSG:2056 \
	-a_ullr 2595000 1205000 2605000 1195000 -ot Float32 "$T/flat.tif" 2>"$T/err" &&
	"$TP" -q "$T/flat.tif" -o "$T/flat.exr" 2>"$T/err"; then
	run "$CR" --terrain "$T/flat.exr" --camera 46.95,7.44 --camera-agl 100 -v -o "$T/a.png" $FAST
	expect_rc 0
	set -- $(camera); [ "${3:-}" = 800 ] || bad "over the 700 m terrain at ${3:-?} m, expected 800"
	run "$CR" --terrain "$T/flat.exr" --view Gurten --camera-agl 0 -v -o "$T/a.png" $FAST
	expect_rc 0
	set -- $(camera); [ "${3:-}" = 700 ] || bad "a view at 0 m above the terrain at ${3:-?} m"
else
	bad "could not make a flat terrain: $(head -c 300 "$T/err")"
fi
# the synthetic Bern DEM: 25 m above the Gurten's summit, as gdallocationinfo reads it
if "$TOP/scripts/make-bern-dem" -r 100 "$T/dem.tif" >/dev/null 2>&1 &&
	"$TP" -q "$T/dem.tif" -o "$T/bern.exr" 2>"$T/err"; then
	h=$(gdallocationinfo -wgs84 -valonly "$T/dem.tif" 7.44361 46.91722)
	run "$CR" --terrain "$T/bern.exr" --view gurten --camera-agl 25 -v -o "$T/a.png" $FAST
	expect_rc 0
	set -- $(camera)
	near "${3:-0}" "$(awk -v h="$h" 'BEGIN { print h + 25 }')" 5 ||
		bad "over the Gurten at ${3:-?} m, the DEM says $h m + 25"
else
	bad "could not make the Bern terrain: $(head -c 300 "$T/err")"
fi
end

begin cloudrender_camera_agl_usage_errors
run "$CR" --camera 46.9,7.4 -o "$T/x.png" $FAST
expect_rc 2; expect_err "the altitude is missing"; expect_err "--camera-agl"
run "$CR" --camera 46.9,7.4,600 --camera-agl 10 -o "$T/x.png" $FAST
expect_rc 2; expect_err "both set the height"
run "$CR" --camera-agl -5 -o "$T/x.png" $FAST
expect_rc 2; expect_err "--camera-agl"
run "$CR" --camera-agl high -o "$T/x.png" $FAST
expect_rc 2; expect_err "--camera-agl"
expect_no_file "$T/x.png"
end

begin cloudrender_view_names_are_case_insensitive
run "$CR" --view gurten -o "$T/g1.png" $FAST; expect_rc 0
run "$CR" --view Gurten -o "$T/g2.png" $FAST; expect_rc 0
run "$CR" --view GURTEN -o "$T/g3.png" $FAST; expect_rc 0
cmp -s "$T/g1.png" "$T/g2.png" && cmp -s "$T/g1.png" "$T/g3.png" || bad "Gurten, GURTEN and gurten differ"
run "$CR" --view Gurtenn -o "$T/x.png" $FAST
expect_rc 2; expect_err "unknown view 'Gurtenn'"
end

begin cloudrender_views_file_adds_named_views
cat >"$T/views" <<'V'
# name     lat      lon     alt_m  az   el   fov  description
rosengarten 46.9513 7.4606 570   250  3    50   Bern's rose garden, over the old town
Chasseral  47.13317 7.05936 1627 120 -2 70
V
run "$CR" --views "$T/views" --view ROSENGARTEN -v -o "$T/r.png" $FAST
expect_rc 0; expect_file "$T/r.png"
[ "$(camera)" = "46.95130 7.46060 570 250.0 3.0" ] || bad "rosengarten: camera '$(camera)'"
grep -q 'fov 50 deg' "$T/err" || bad "rosengarten: not its 50 deg field"
run "$CR" --views "$T/views" --list-views
expect_rc 0; expect_out "rosengarten"; expect_out "Bern's rose garden"; expect_out "Chasseral"
expect_out "gurten"; expect_out "bantiger"
# the file's view beside the built-in ones; still case-insensitive
run "$CR" --views "$T/views" --view gurten -v -o "$T/r.png" $FAST
expect_rc 0
# a default file in $XDG_CONFIG_HOME
mkdir -p "$T/cfg/cloudscape"; cp "$T/views" "$T/cfg/cloudscape/views"
XDG_CONFIG_HOME="$T/cfg" run "$CR" --view chasseral -v -o "$T/c.png" $FAST
expect_rc 0
set -- $(camera); [ "${3:-}" = 1627 ] || bad "the XDG file's Chasseral at ${3:-?} m"
XDG_CONFIG_HOME="$T/none" run "$CR" --view chasseral -o "$T/x.png" $FAST
expect_rc 2; expect_err "unknown view 'chasseral'"
# a bad default file stops what names a view, not the other renders
mkdir -p "$T/bad/cloudscape"; echo 'x 1 2' >"$T/bad/cloudscape/views"
XDG_CONFIG_HOME="$T/bad" run "$CR" -o "$T/d.png" $FAST
expect_rc 0
XDG_CONFIG_HOME="$T/bad" run "$CR" --view gurten -o "$T/x.png" $FAST
expect_rc 1; expect_err "views:1:"; expect_no_file "$T/x.png"
end

begin cloudrender_views_file_errors_name_the_line
printf 'ok 46.9 7.4 600 10 0 60\nbad 46.9 7.4 600 10 0\n' >"$T/v1"
run "$CR" --views "$T/v1" --view ok -o "$T/x.png" $FAST
expect_rc 1; expect_err "v1:2:"; expect_err "field of view is missing"; expect_no_file "$T/x.png"
printf 'a 46.9 7.4 600 10 95 60\n' >"$T/v2"
run "$CR" --views "$T/v2" --list-views
expect_rc 1; expect_err "v2:1: the elevation must be -90..90"
printf 'dup 46.9 7.4 600 10 0 60\nDUP 46.9 7.4 600 10 0 60\n' >"$T/v3"
run "$CR" --views "$T/v3" --list-views
expect_rc 1; expect_err "a second view named 'DUP'"
printf 'b@d 46.9 7.4 600 10 0 60\n' >"$T/v4"
run "$CR" --views "$T/v4" --list-views
expect_rc 1; expect_err "v4:1: a name is letters"
run "$CR" --views "$T/absent" --list-views
expect_rc 1; expect_err "absent"
end

begin cloudrender_keywords_are_case_insensitive
run "$CR" --projection fisheye --integrator march --march skip -o "$T/k1.png" $FAST
expect_rc 0
run "$CR" --projection FishEye --integrator MARCH --march Skip --quality LOW -o "$T/k2.png" $FAST
expect_rc 0
cmp -s "$T/k1.png" "$T/k2.png" || bad "keywords in capitals rendered another image"
run "$CR" --projection Fishbowl -o "$T/x.png" $FAST
expect_rc 2; expect_err "unknown projection 'Fishbowl'"
end
