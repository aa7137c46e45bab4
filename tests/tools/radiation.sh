# The clouds' optical depth fitted to the forecast's beam, as a user runs
# it (cloudrender --cloud-depth; render/beam_fit.c).  The expected values
# come from the forecast itself: its GHI, which the fit does not read (it
# reads the DNI), against the area GHI our light transport produces.
. "$TOP/tests/tools/lib.sh"
plan 7
CR="$BIN/cloudrender"
WI="$BIN/wxinterp"
REAL="${DATA:-$TOP/../shared/data}/weather/meteoblue-basic-clouds-solar-1h.json"

# mean_abs_log: the mean |ln(ours / forecast)| of the area GHI over the
# frames of $T/oc.jsonl, from cloudrender's --stats lines in $T/err
mean_abs_log() {
	grep -o '"ghi_w_m2":[0-9.]*' "$T/oc.jsonl" | cut -d: -f2 >"$T/fc"
	grep -o '"area":{[^}]*}' "$T/err" | sed 's/.*"ghi":\([0-9.]*\).*/\1/' >"$T/ours"
	paste "$T/fc" "$T/ours" | awk '{ if (NF < 2 || $1 <= 0 || $2 <= 0) bad = 1;
		d = log($2 / $1); s += d < 0 ? -d : d; n++ }
		END { if (bad || n != 5) print "none"; else printf "%.3f\n", s / n }'
}

# The capture's overcast afternoon, 2024-10-07 12 to 16 UTC (cover 0.97 to
# 1, the forecast's DNI 48 to 131 W/m2, its GHI 262 to 472): the genera's
# depths leave the ground 0.47 too dark in the mean of |ln| (145 against
# 262, 176 against 403 W/m2 at 12 and 13 UTC); the depths fitted to the
# DNI bring it to 0.17, measured; more than 0.25, or the genera's under
# 0.35 (the fit not applied where asked, or applied where not), fails.
begin cloudrender_overcast_afternoon_ground_light_near_the_forecasts
if [ -f "$REAL" ]; then
	"$WI" "$REAL" --from 2024-10-07T12:00Z --to 2024-10-07T16:00Z >"$T/oc.jsonl" ||
		bad "wxinterp failed"
	run "$CR" --wx "$T/oc.jsonl" --size 64x36 --quality low -q --stats -o "$T/f%d.png"
	expect_rc 0
	fit=$(mean_abs_log)
	awk -v m="$fit" 'BEGIN { exit !(m != "none" && m <= 0.25) }' ||
		bad "fitted: mean |ln(ours / forecast)| of the GHI $fit, expected <= 0.25"
	run "$CR" --wx "$T/oc.jsonl" --cloud-depth genus --size 64x36 --quality low -q --stats \
		-o "$T/g%d.png"
	expect_rc 0
	genus=$(mean_abs_log)
	awk -v m="$genus" 'BEGIN { exit !(m != "none" && m >= 0.35) }' ||
		bad "genus: mean |ln(ours / forecast)| of the GHI $genus, expected >= 0.35"
	end
else
	skip cloudrender_overcast_afternoon_ground_light_near_the_forecasts "no $REAL"
fi

# The scale is reported: -v says what the fit did and why not, --stats
# gives it; --time drops the forecast's radiation; 2024-10-07T13Z's sheets are thinned (the genera's altostratus
# over cumulus let no beam through where the forecast lets 15 % through).
begin cloudrender_cloud_depth_is_reported
if [ -f "$REAL" ]; then
	"$WI" "$REAL" --at 2024-10-07T13:00Z >"$T/h13.json" || bad "wxinterp failed"
	run "$CR" --wx "$T/h13.json" --size 32x18 --quality low -v --stats -o "$T/a.png"
	expect_rc 0
	expect_err "times the genera's, fitted to the forecast's DNI of 123 W/m2 (--cloud-depth forecast)"
	k=$(grep -o '"cloud_depth_scale":[0-9.]*' "$T/err" | cut -d: -f2)
	awk -v k="$k" 'BEGIN { exit !(k != "" && k > 0.02 && k < 0.5) }' ||
		bad "cloud_depth_scale '$k', expected between 0.02 and 0.5"
	run "$CR" --wx "$T/h13.json" --cloud-depth GENUS --size 32x18 --quality low -v --stats \
		-o "$T/b.png"
	expect_rc 0
	expect_err "cloud depth: the genera's (--cloud-depth genus)"
	expect_err '"cloud_depth_scale":1.0000'
	# at another time the forecast's radiation, its hour's, is dropped
	# (its DNI under a sun of 16 deg thinned the sheets to the bound)
	run "$CR" --wx "$T/h13.json" --time 2024-10-07T20:30Z --size 32x18 --quality low -v \
		--stats -o "$T/e.png"
	expect_rc 0
	expect_err "cloud depth: the genera's (no forecast radiation at the state's time)"
	expect_err '"cloud_depth_scale":1.0000'
	end
else
	skip cloudrender_cloud_depth_is_reported "no $REAL"
fi

# Without the forecast's radiation (the built-in state, cloudwx/1 files)
# nothing is fitted; a bad value is a usage error.
begin cloudrender_cloud_depth_without_radiation_and_bad_values
run "$CR" --size 32x18 --quality low --noise-size 16 -v --stats -o "$T/c.png"
expect_rc 0
expect_err "cloud depth: the genera's (no forecast radiation at the state's time)"
expect_err '"cloud_depth_scale":1.0000'
run "$CR" --cloud-depth thick --size 32x18 -o "$T/d.png"
expect_rc 2
expect_err "cloudrender: --cloud-depth: 'thick' is not forecast or genus"
expect_no_file "$T/d.png"
end

# The sky's level (--sky-level) against the forecast's own diffuse light
# at the capture's one cloudless hour, 2024-10-13T12:00Z (total cover 0,
# no layer; visibility 8 km, the sun 35 deg up): its DHI is 167.6 W/m2.
# The Ineichen-Perez clear sky's level gives 179.5, measured (+7 %);
# Preetham's own 210.9 (+26 %).  ineichen more than 12 % off, or preetham
# within 20 % (the level not changed where asked, or where not), fails.
begin cloudrender_sky_level_gives_a_cloudless_hours_diffuse_light
if [ -f "$REAL" ]; then
	"$WI" "$REAL" --at 2024-10-13T12:00Z >"$T/c12.json" || bad "wxinterp failed"
	grep -q '"layers":\[\]' "$T/c12.json" || bad "2024-10-13T12Z has layers"
	for level in ineichen preetham; do
		run "$CR" --wx "$T/c12.json" --sky-level $level --size 64x36 --quality low -q --stats \
			-o "$T/s.png"
		expect_rc 0
		dhi=$(grep -o '"area":{[^}]*}' "$T/err" | sed 's/.*"dhi":\([0-9.]*\).*/\1/')
		awk -v d="$dhi" -v l=$level 'BEGIN { r = d / 167.6; e = r < 1 ? 1 - r : r - 1;
			exit !(d != "" && (l == "ineichen" ? e <= 0.12 : e >= 0.2)) }' ||
			bad "--sky-level $level: the area DHI $dhi W/m2 against the forecast's 167.6"
	done
	run "$CR" --wx "$T/c12.json" --sky-level ineichen --size 32x18 --quality low -v --stats \
		-o "$T/s.png"
	expect_err "times Preetham's, the Ineichen-Perez clear sky's diffuse light (--sky-level ineichen)"
	expect_err '"sky_level_scale":0.'
	run "$CR" --wx "$T/c12.json" --size 32x18 --quality low -v --stats -o "$T/s.png"
	expect_err "sky level: Preetham's (--sky-level preetham)"
	expect_err '"sky_level_scale":1.0000'
	run "$CR" --sky-level bright -o "$T/s.png"
	expect_rc 2
	expect_err "--sky-level: 'bright' is not preetham or ineichen"
	end
else
	skip cloudrender_sky_level_gives_a_cloudless_hours_diffuse_light "no $REAL"
fi

# radiation-study's summaries by the forecast's cover, over stand-ins for
# wxinterp (twelve hours of known radiation) and cloudrender (ours by the
# hour, below), the figures computed apart from the script (Python, the
# rules of radiation-study(1)): the hour of 40 W/m2 left out (under 50);
# the sun 5 deg up counted in the ln summary, not in the transmissions;
# fog (300 m) and far sites not in the transmissions either; covers 0.2
# and 0.8 in the bins they open; the hour with convective rain cloudless
# only once its rain is gone too (the stand-in gives 700 W/m2 otherwise);
# an hour whose render has no irradiance left out of every summary.
begin radiation_study_summarises_by_cover
cat >"$T/fake-wx" <<'EOS'
#!/bin/sh
while read -r hh g n d c v extra; do
	printf '{"time_utc":"2024-01-01T%s:00:00Z","layers":[{"genus":"cumulus","coverage":0.5}],"precipitation_mm_h":%s,"convective_mm_h":%s,"visibility_m":%s,%s"observed":{"ghi_w_m2":%s,"dni_w_m2":%s,"dhi_w_m2":%s,"total_cloud_cover":%s}}\n' \
		"$hh" "$([ "$extra" = conv ] && echo 2 || echo 0.4)" "$([ "$extra" = conv ] && echo 2 || echo 0)" \
		"$v" "$([ "$extra" = far ] && echo '"far":[{"layers":[{"genus":"stratus"}]}],')" "$g" "$n" "$d" "$c"
done <<'EOH'
10 500 600 100 0.1 20000 -
11 400 300 200 0.5 20000 -
12 300 100 250 0.9 20000 -
13 320 100 280 0.95 20000 -
14 200 100 150 0.6 300 -
15 450 200 200 0.2 20000 -
16 250 50 220 0.8 20000 -
17 40 10 30 0.5 20000 -
18 300 100 200 0.5 20000 -
19 300 100 200 0.5 20000 far
20 350 150 200 0.3 20000 conv
21 300 100 200 0.5 20000 -
EOH
EOS
cat >"$T/fake-cr" <<'EOS'
#!/bin/sh
while [ $# -gt 0 ]; do [ "$1" = --wx ] && wx=$2; shift; done
el=40
case $(grep -o 'T[0-9][0-9]:' "$wx") in
T10:) g=600 d=150 ;; T11:) g=360 d=200 ;; T12:) g=240 d=200 ;; T13:) g=416 d=350 ;;
T14:) g=180 d=150 ;; T15:) g=495 d=220 ;; T16:) g=175 d=198 ;; T17:) g=100 d=30 ;;
T18:) g=150 d=100 el=5 ;; T19:) g=330 d=210 ;; T20:) g=280 d=200 ;; T21:) g=null d=null ;;
esac
# without clouds 1000 W/m2, or 700 while it still rains
if grep -q '"layers":\[\]' "$wx"; then
	g=700
	grep -q '"precipitation_mm_h":0[,}].*"convective_mm_h":0[,}]' "$wx" && g=1000
fi
printf '{"sun":{"azimuth_deg":0,"elevation_deg":%s},"cloud_fraction":0.5,"irradiance_w_m2":{"area":{"size_km":10,"ghi":%s,"dni":0,"dhi":%s}}}\n' $el $g $d >&2
EOS
chmod +x "$T/fake-wx" "$T/fake-cr"
WXINTERP="$T/fake-wx" CLOUDRENDER="$T/fake-cr" run "$TOP/scripts/radiation-study" any.json
expect_rc 0
expect_out "cover < 0.2: 1 hours, ln(ours/forecast) GHI mean +0.182 rms 0.182, DHI mean +0.405 rms 0.405"
expect_out "cover 0.2-0.8: 6 hours, ln(ours/forecast) GHI mean -0.156 rms 0.308, DHI mean -0.092 rms 0.286"
expect_out "cover >= 0.8: 3 hours, ln(ours/forecast) GHI mean -0.106 rms 0.286, DHI mean -0.035 rms 0.192"
grep -q "transmission" "$T/out" && bad "the clouds' transmission without STUDY_CLEAR"
# STUDY_CLEAR=1: Kasten & Czeplak's 1 - 0.75 N^3.4, the transmissions
# ours / 1000 and the forecast's / 1000 (the same Python)
STUDY_CLEAR=1 WXINTERP="$T/fake-wx" CLOUDRENDER="$T/fake-cr" run "$TOP/scripts/radiation-study" any.json
expect_rc 0
expect_out "cover 0-0.2: 1 hours, the clouds' transmission (GHI over our cloudless GHI) 0.60, the forecast's 0.50, Kasten & Czeplak's 1.00"
expect_out "cover 0.2-0.5: 2 hours, the clouds' transmission (GHI over our cloudless GHI) 0.39, the forecast's 0.40, Kasten & Czeplak's 0.99"
expect_out "cover 0.5-0.8: 1 hours, the clouds' transmission (GHI over our cloudless GHI) 0.36, the forecast's 0.40, Kasten & Czeplak's 0.93"
expect_out "cover 0.8-0.95: 2 hours, the clouds' transmission (GHI over our cloudless GHI) 0.21, the forecast's 0.28, Kasten & Czeplak's 0.56"
expect_out "cover 0.95-1: 1 hours, the clouds' transmission (GHI over our cloudless GHI) 0.42, the forecast's 0.32, Kasten & Czeplak's 0.37"
end

# mean_luma FILE.exr: the mean luminance (Rec. 709 weights) of its pixels
mean_luma() {
	printf '%.17g %.17g %.17g\n' $("$HELPERS/exrpixels" "$1" R G B | sed 1d) |
		awk '{ s += 0.2126 * $1 + 0.7152 * $2 + 0.0722 * $3; n++ } END { if (n) printf "%.6g\n", s / n }'
}

# The capture's hour at TIME rendered by the march (high, no haze, which
# the path tracer does not simulate) and by the path tracer (the mean of
# two seeds of 128 paths a pixel), SIZE, the noise 32 cubed: the ratio of
# their mean luminances within LO to HI.
#   march_against_path_tracer TIME SIZE LO HI
march_against_path_tracer() {
	"$WI" "$REAL" --at "$1" >"$T/hour.json" || bad "wxinterp failed"
	run "$CR" --wx "$T/hour.json" --noise-size 32 --size "$2" --quality high --no-haze -q \
		-o "$T/march.exr"
	expect_rc 0
	for seed in 1 2; do
		run "$CR" --wx "$T/hour.json" --noise-size 32 --size "$2" --integrator reference \
			--spp 128 --seed $seed -q -o "$T/ref$seed.exr"
		expect_rc 0
	done
	m=$(mean_luma "$T/march.exr")
	r=$(awk -v a="$(mean_luma "$T/ref1.exr")" -v b="$(mean_luma "$T/ref2.exr")" \
		'BEGIN { printf "%.6g\n", (a + b) / 2 }')
	awk -v m="$m" -v r="$r" -v lo="$3" -v hi="$4" \
		'BEGIN { exit !(r > 0 && m / r >= lo && m / r <= hi) }' ||
		bad "the march's mean luminance $m, the path tracer's $r: expected $3 to $4 times"
}

# The capture's rain hour, 2024-10-07 19Z (nimbostratus 70 %, its depth
# fitted 3.53 times, 0.6 mm/h), at 16x9 (the references' means 0.78 and
# 0.50: thick cloud's paths are heavy-tailed).  The march measured 0.70
# of the path tracer's (0.76 while the cumulus under the deck took the
# area's mean light at its top: cloudrender(1), Light); lit by the
# area's mean light and by all of it, its rain made the picture 3.7 times
# as bright.  Outside 0.6 to 1.6 fails.
begin cloudrender_rain_hour_as_bright_as_the_path_tracer_draws_it
if [ -f "$REAL" ]; then
	march_against_path_tracer 2024-10-07T19:00Z 16x9 0.6 1.6
	end
else
	skip cloudrender_rain_hour_as_bright_as_the_path_tracer_draws_it "no $REAL"
fi

# The capture's fair hour (2024-10-06 15Z: cirrus of 0.32 cover, optical
# depth 0.56 in cloud, over a few cumulus), at 32x18, within 7 %.  The
# cirrus, lit by the march's model of the diffuse light rather than light
# fields, made it 11 % too bright (measured +11.0 %, now +2.0 %;
# cloudrender(1), Light).
begin cloudrender_fair_hours_cirrus_as_bright_as_the_path_tracer_draws_it
if [ -f "$REAL" ]; then
	march_against_path_tracer 2024-10-06T15:00Z 32x18 0.93 1.07
	end
else
	skip cloudrender_fair_hours_cirrus_as_bright_as_the_path_tracer_draws_it "no $REAL"
fi
