# cloudrender -v (what it renders, the time of each phase), the progress
# bar's elapsed time and ETA on a terminal, and the default view.
. "$TOP/tests/tools/lib.sh"
plan 8
CR="$BIN/cloudrender"
WX="$BIN/wxinterp"
FAST="--quality low --noise-size 32 --size 64x36"
MB="${DATA:-}/weather/meteoblue-basic-clouds-solar-1h.json"
# the light caches -v reports: "volumes million-cells"
volumes() { sed -n 's/^cloudrender: light cache: \([0-9]*\) volumes*, \([0-9.]*\) million.*/\1 \2/p' "$T/err"; }

begin cloudrender_verbose_says_what_it_renders
run "$CR" -v $FAST -o "$T/a.png"; expect_rc 0
# the built-in state (man 5 cloudwx): Bern, cumulus and cirrus
expect_err "cloudrender: time 2021-06-14T14:00:00Z, site Bern 46.9500, 7.4400, 540 m"
expect_err "cloudrender: sun azimuth "
expect_err "cloudrender: camera 46.95000, 7.44000, 542 m, looking azimuth "
expect_err "cloudrender: layer 1: cumulus, cover 0.35, base 1500 m, top 2700 m"
expect_err "cloudrender: layer 2: cirrus, cover 0.20, base 9000 m, top 9600 m"
expect_err "cloudrender: effects: sun sky clouds ground haze"
expect_err "cloudrender: quality low: 24 steps, 8 light steps"
expect_err "cloudrender: time: noise "
# the sun agrees with --stats (NOAA's algorithm), to the printed 0.1 deg
run "$CR" -v --stats $FAST -o "$T/a.png"; expect_rc 0
az=$(sed -n 's/.*"sun":{"azimuth_deg":\([0-9.]*\),.*/\1/p' "$T/err")
grep -q "sun azimuth $(printf '%.1f' "$az") deg" "$T/err" || bad "-v sun azimuth differs from --stats $az"
# the description comes before the render's end: the time line is last
tail -n 2 "$T/err" | grep -q "time: noise" || bad "the phase times are not at the end"
run "$CR" $FAST -o "$T/a.png"; expect_rc 0
[ -s "$T/err" ] && bad "without -v stderr is not empty: $(head -c 200 "$T/err")"
end

# --light-march auto (low's): a layer's volume only for a frame of a pixel
# for every 32 of its cells (low's volumes: 8 x 83333 cells at most, a
# tenth more for whole columns), the layer marched in a smaller one
begin cloudrender_light_cache_auto_builds_only_what_the_frame_pays_for
run "$CR" -v $FAST --light-march cache -o "$T/c.png"; expect_rc 0
set -- $(volumes)
[ "${1:-0}" -ge 2 ] && [ "$(echo "${2:-0} > 0.5" | bc)" -eq 1 ] ||
	bad "--light-march cache at 64x36 built '$(volumes)' (volumes, million cells)"
all=${1:-0}
run "$CR" -v $FAST -o "$T/a.png"; expect_rc 0
[ "$(volumes)" = "0 0.00" ] || bad "auto at 64x36 (2304 pixels) built '$(volumes)'"
run "$CR" -v $FAST --size 320x180 -o "$T/a.png"; expect_rc 0
set -- $(volumes)
[ "${1:-0}" -eq "$all" ] || bad "auto at 320x180 built '$(volumes)', expected all $all volumes"
end

# The study's cumulonimbus side view at high with --$1 on and with it
# off: the same pixels, or the case fails (a light for what, $2, the
# scene does not have)
cumulonimbus_either_way() {
	cb="--wx $TOP/tests/scenes/cumulonimbus-side.json $(cat "$TOP/tests/scenes/cumulonimbus-side.args")"
	for v in on off; do
		# shellcheck disable=SC2086
		run "$CR" $cb --quality high --$1 $v --noise-size 32 --size 48x27 -o "$T/cb-$1-$v.exr"
		expect_rc 0
	done
	same_pixels "$T/cb-$1-on.exr" "$T/cb-$1-off.exr" || bad "--$1 changed the pixels of $2"
}

# --heap-towers: the built-in cumulus (35 % cover) takes the towers' light
# at high, and its lattice with it (a volume at any size), not at medium
# or with it off; -v says which; a cumulonimbus alone renders the same
# bytes either way
begin cloudrender_heap_towers_follow_the_preset_and_the_option
heaps() { grep -c "heaps lit as towers" "$T/err"; }
for q in "high:1 1" "high --heap-towers off:0 0" "medium:0 0" "medium --heap-towers on:1 1"; do
	opts=${q%%:*} want=${q#*:}
	# shellcheck disable=SC2086
	run "$CR" -v --quality $opts --noise-size 32 --size 64x36 --light-march geometric \
		-o "$T/h.png"; expect_rc 0
	set -- $(volumes)
	[ "${1:-0} $(heaps)" = "$want" ] ||
		bad "--quality $opts: '${1:-0}' volumes, '$(heaps)' heaps as towers, expected '$want'"
done
cumulonimbus_either_way heap-towers "a scene without cumulus"
end

# --deck-lattice: the rain deck of tests/scenes (nimbostratus of 70 %)
# takes the deck's lattice with the exchange at high, by diffusion alone
# at medium, none with it off; on is exchange; -v says which, and the
# pixels change with each; a scene without a deck (the cumulonimbus, whose
# towers always take the exchange) renders the same bytes either way
begin cloudrender_deck_lattice_follows_the_preset_and_the_option
DB="--wx $TOP/tests/scenes/broken-deck-below.json $(cat "$TOP/tests/scenes/broken-deck-below.args")"
deck() { sed -n "s/^cloudrender: quality .*, decks' lattice\( with the exchange\)\{0,1\}.*$/lattice\1/p" "$T/err"; }
for q in "high:lattice with the exchange:h2" "high --deck-lattice off::h0" "medium:lattice:m1" \
	"medium --deck-lattice off::m0" "medium --deck-lattice exchange:lattice with the exchange:m2" \
	"medium --deck-lattice on:lattice with the exchange:mon"; do
	opts=${q%%:*} rest=${q#*:}
	want=${rest%%:*} name=${rest#*:}
	# shellcheck disable=SC2086
	run "$CR" $DB -v --quality $opts --noise-size 32 --size 32x18 --no-haze -o "$T/d-$name.exr"
	expect_rc 0
	[ "$(deck)" = "$want" ] || bad "--quality $opts: -v says '$(deck)', not '$want'"
done
same_pixels "$T/d-h2.exr" "$T/d-h0.exr" && bad "--deck-lattice off did not change the deck at high"
same_pixels "$T/d-m1.exr" "$T/d-m0.exr" && bad "--deck-lattice off did not change the deck at medium"
same_pixels "$T/d-m2.exr" "$T/d-m1.exr" && bad "--deck-lattice exchange did not change the deck at medium"
same_pixels "$T/d-mon.exr" "$T/d-m2.exr" || bad "--deck-lattice on is not exchange"
cumulonimbus_either_way deck-lattice "a scene without a deck"
cb="--wx $TOP/tests/scenes/cumulonimbus-side.json $(cat "$TOP/tests/scenes/cumulonimbus-side.args")"
# shellcheck disable=SC2086
run "$CR" $cb --quality high --deck-lattice diffusion --noise-size 32 --size 48x27 -o "$T/cb-diffusion.exr"
expect_rc 0
same_pixels "$T/cb-diffusion.exr" "$T/cb-deck-lattice-on.exr" ||
	bad "--deck-lattice diffusion changed the towers' exchange"
run "$CR" $DB --deck-lattice both -o "$T/bad.exr"
expect_rc 2
end

# --ground-sky: the ground under the built-in cumulus takes the field's
# light at high, the columns' at medium or with columns asked for, the
# dome's with dome asked for; -v says which, and the ground's pixels change
# with each; under a clear sky there is no deck and the same bytes either
# way.  -v says why a field or dome asked for was not traced: no clouds,
# fog, a frame that sees no ground
begin cloudrender_ground_sky_follows_the_preset_and_the_option
lit() { sed -n "s/^cloudrender: ground's diffuse light: \(.*\)$/\1/p" "$T/err"; }
for q in "high:field's" "high --ground-sky columns:columns'" "medium:columns'" "medium --ground-sky dome:dome's" \
	"medium --ground-sky field:field's"; do
	opts=${q%%:*} want=${q#*:}
	# shellcheck disable=SC2086
	run "$CR" -v --quality $opts --noise-size 32 --size 64x36 -o "$T/g.exr"; expect_rc 0
	[ "$(lit)" = "the $want" ] || bad "--quality $opts: '$(lit)', expected 'the $want'"
	cp "$T/g.exr" "$T/g-${want%%\'*}.exr"
done
same_pixels "$T/g-columns.exr" "$T/g-dome.exr" && bad "--ground-sky dome left the ground under cumulus as it was"
same_pixels "$T/g-dome.exr" "$T/g-field.exr" && bad "--ground-sky field left the ground as the dome lit it"
printf '%s\n' '{"schema":"cloudwx/1","time_utc":"2021-06-14T11:00:00Z","site":{"name":"Bern","lat_deg":46.95,"lon_deg":7.44,"alt_m":540},"layers":[],"precipitation_mm_h":0,"wind":{"speed_m_s":4,"from_deg":250},"visibility_m":40000}' >"$T/clear.json"
for g in field dome columns; do
	run "$CR" --wx "$T/clear.json" --quality high --ground-sky $g --noise-size 32 --size 48x27 \
		--look 150,-5 -o "$T/clear-$g.exr"; expect_rc 0
done
same_pixels "$T/clear-dome.exr" "$T/clear-columns.exr" && same_pixels "$T/clear-field.exr" "$T/clear-columns.exr" ||
	bad "--ground-sky changed a clear sky's pixels"
# fog under a clear sky, and under stratocumulus (80 %, 1.5 to 2.1 km)
sed 's/"visibility_m":40000/"visibility_m":300/' "$T/clear.json" >"$T/clear-fog.json"
sed 's/"layers":\[\]/"layers":[{"genus":"stratocumulus","coverage":0.8,"base_m":1500,"top_m":2100}]/' \
	"$T/clear-fog.json" >"$T/cloud-fog.json"
for c in "--wx $T/clear.json --quality high|the clear sky's (no clouds)" \
	"--wx $T/clear.json --quality medium|the clear sky's (no clouds)" \
	"--wx $T/clear-fog.json --quality high|the clear sky's and the fog's (no clouds over the fog)" \
	"--wx $T/cloud-fog.json --quality high|the columns' and the fog's, none traced (fog: its light is solved from the columns')" \
	"--wx $T/cloud-fog.json --quality medium|the columns' and the fog's" \
	"--look 150,40 --quality high --no-haze|the columns', none traced (the frame sees no ground)" \
	"--look 150,40 --quality high|the field's, for the haze and the rain under the clouds (the frame sees no ground)" \
	"--look 150,40 --quality high --ground-sky dome|the dome's, for the haze and the rain under the clouds (the frame sees no ground)" \
	"--look 150,40 --quality high --ground-sky dome --no-haze|the columns', none traced (the frame sees no ground)"; do
	# shellcheck disable=SC2086
	run "$CR" -v ${c%%|*} --noise-size 32 --size 48x27 -o "$T/why.exr"; expect_rc 0
	line=$(sed -n "s/^cloudrender: ground's diffuse light: //p" "$T/err")
	[ "$line" = "${c#*|}" ] || bad "${c%%|*}: -v said '$line', expected '${c#*|}'"
done
end

begin cloudrender_progress_shows_elapsed_and_eta_on_a_terminal
if command -v script >/dev/null 2>&1; then
	script -qc "'$CR' $FAST -o '$T/b.png'" /dev/null >"$T/tty" 2>&1 </dev/null
	tr '\r' '\n' <"$T/tty" | grep -q 'rendering \[.*\] 100% [0-9]*:[0-9][0-9] ETA 0:00' ||
		bad "no bar with elapsed time and ETA on a terminal: $(tr '\r' '\n' <"$T/tty" | tail -n 2)"
	run "$CR" $FAST -o "$T/b.png"
	grep -q ETA "$T/err" && bad "a progress bar without a terminal"
	end
else
	skip cloudrender_progress_shows_elapsed_and_eta_on_a_terminal "no script(1)"
fi

begin cloudrender_default_view_looks_away_from_the_sun
if [ -f "$MB" ]; then
	# Montevideo, 2024-10-07 15:00 UTC: not Bern's south-south-east
	"$WX" --at 2024-10-07T15:00Z "$MB" >"$T/mv.json"
	run "$CR" --wx "$T/mv.json" -v $FAST -o "$T/mv.png"; expect_rc 0
	sun=$(sed -n 's/.*sun azimuth \([0-9.]*\) deg.*/\1/p' "$T/err")
	look=$(sed -n 's/.*looking azimuth \([0-9.]*\) deg.*/\1/p' "$T/err")
	awk -v s="$sun" -v l="$look" 'BEGIN { d = l - s - 180; while (d < -180) d += 360; while (d > 180) d -= 360
		exit !(d < 0.15 && d > -0.15) }' || bad "look azimuth $look is not opposite the sun's $sun"
	expect_err "(default view: away from the sun"
	# an explicit --look is kept
	run "$CR" --wx "$T/mv.json" -v --look 160,8 $FAST -o "$T/mv.png"; expect_rc 0
	expect_err "looking azimuth 160.0 deg, elevation 8.0 deg"
	end
else
	skip cloudrender_default_view_looks_away_from_the_sun "no $MB (shared data absent)"
fi

begin cloudrender_hazy_default_view_looks_up_to_the_clouds
# 2 km visibility under the built-in cumulus (base 960 m above the eye):
# sin e = 3.912/2000 * 1200 * (1 - exp(-960/1200)) / 1.5 = 0.859, e = 59.2
# deg, less a quarter of the 43.1-deg frame: 48.5 deg
"$WX" --template --set visibility=2000 >"$T/hz.json"
run "$CR" --wx "$T/hz.json" -v --quality low --noise-size 32 --size 64x36 -o "$T/hz.png"; expect_rc 0
el=$(sed -n 's/.*looking azimuth [0-9.]* deg, elevation \([0-9.]*\) deg.*/\1/p' "$T/err")
ref=$(awk 'BEGIN { pi = atan2(0, -1); s = 3.912 / 2000 * 1200 * (1 - exp(-958 / 1200)) / 1.5
	e = atan2(s, sqrt(1 - s * s)) * 180 / pi; v = 2 * atan2(sin(35 * pi / 180) / cos(35 * pi / 180) * 36 / 64, 1) * 180 / pi
	printf "%.1f", e - v / 4 }')
awk -v a="$el" -v b="$ref" 'BEGIN { d = a - b; exit !(d < 0.25 && d > -0.25) }' || bad "hazy default elevation $el, expected $ref"
expect_err "raised to see the lowest base through the haze"
end
