# scripts/timelapse: frames of a provider file by make, then an H.264 MP4.
# Each frame is checked against the same time rendered by hand, the camera
# held at the first time's default view (wxinterp
# --at T | cloudrender), the video with ffprobe (Debian's ffmpeg).
. "$TOP/tests/tools/lib.sh"
plan 6
TL="$TOP/scripts/timelapse"
WI="$BIN/wxinterp"
CR="$BIN/cloudrender"
REAL="${DATA:-$TOP/../shared/data}/weather/meteoblue-basic-clouds-solar-1h.json"
export WXINTERP="$WI" CLOUDRENDER="$CR" NOISEBAKE="$BIN/noisebake"
ARGS="--size 32x18 --step 20m -j 2"
ROPTS="--quality low"

have_ffmpeg=0
command -v ffmpeg >/dev/null 2>&1 && command -v ffprobe >/dev/null 2>&1 && have_ffmpeg=1
"$BIN/noisebake" -q -s 16 -o "$T/noise.exr"
# png_ok FILE: a whole PNG (netpbm reads it to its end)
png_ok() { pngtopnm "$1" >/dev/null 2>&1; }

begin timelapse_renders_each_time_as_wxinterp_and_cloudrender_do_and_encodes_h264
if [ ! -f "$REAL" ]; then
	skip timelapse_renders_each_time_as_wxinterp_and_cloudrender_do_and_encodes_h264 "no $REAL (shared data absent)"
elif [ $have_ffmpeg -eq 0 ]; then
	skip timelapse_renders_each_time_as_wxinterp_and_cloudrender_do_and_encodes_h264 "ffmpeg is not installed (Debian's ffmpeg; make deps installs it)"
else
	run "$TL" "$REAL" 2024-10-13T14:00Z 2024-10-13T14:40Z $ARGS --fps 5 --noise "$T/noise.exr" -o "$T/a" -- $ROPTS
	expect_rc 0
	expect_only_files "$T/a/frames" 3
	# the camera held for the whole video: FROM's default view (as -v says it)
	look=$("$WI" --at 2024-10-13T14:00Z "$REAL" | "$CR" -v --wx - --noise "$T/noise.exr" \
		--size 32x18 $ROPTS -o "$T/probe.png" 2>&1 |
		sed -n 's/.*looking azimuth \([0-9.]*\) deg, elevation \([-0-9.]*\) deg.*/\1,\2/p')
	[ -n "$look" ] || bad "no camera in cloudrender -v"
	i=0
	for t in 14:00 14:20 14:40; do
		f=$(printf '%s/a/frames/%05d.png' "$T" $i)
		"$WI" --at "2024-10-13T${t}Z" "$REAL" | "$CR" -q --wx - --noise "$T/noise.exr" \
			--size 32x18 $ROPTS --look "$look" -o "$T/hand.png" || bad "the hand render of $t failed"
		cmp -s "$f" "$T/hand.png" || bad "frame $i is not 2024-10-13T${t}Z as rendered by hand"
		i=$((i + 1))
	done
	cmp -s "$T/a/frames/00000.png" "$T/a/frames/00002.png" && bad "14:00 and 14:40 are the same picture"
	v=$(ffprobe -v error -select_streams v:0 -count_frames -show_entries \
		stream=codec_name,pix_fmt,width,height,r_frame_rate,nb_read_frames -of csv=p=0 \
		"$T/a/timelapse.mp4" 2>&1)
	[ "$v" = "h264,32,18,yuv420p,5/1,3" ] || bad "video: '$v', expected h264,32,18,yuv420p,5/1,3"
	ls -A "$T/a" | grep -q tmp && bad "a temporary was left: $(ls -A "$T/a")"
fi
end

begin timelapse_resumes_and_renders_only_what_is_missing_or_changed
if [ ! -f "$REAL" ]; then
	skip timelapse_resumes_and_renders_only_what_is_missing_or_changed "no $REAL (shared data absent)"
else
	run "$TL" "$REAL" 2024-10-13T14:00Z 2024-10-13T15:00Z $ARGS --noise-size 16 --no-video -o "$T/b" -- $ROPTS
	expect_rc 0
	expect_only_files "$T/b/frames" 4
	[ -s "$T/b/noise.exr" ] || bad "no noise baked into the folder"
	cp "$T/b/Makefile" "$T/mk1"
	cp "$T/b/frames/00002.png" "$T/f2.png"
	rm "$T/b/frames/00002.png"
	touch -d '2001-01-01' "$T/b/frames/00000.png" "$T/b/frames/00001.png" "$T/b/frames/00003.png"
	touch -d '2000-01-01' "$T/b/Makefile" "$T/b/noise.exr"
	run "$TL" "$REAL" 2024-10-13T14:00Z 2024-10-13T15:00Z $ARGS --noise-size 16 --no-video -o "$T/b" -- $ROPTS
	expect_rc 0
	cmp -s "$T/mk1" "$T/b/Makefile" || bad "the same arguments wrote another Makefile"
	cmp -s "$T/f2.png" "$T/b/frames/00002.png" || bad "the missing frame came back different"
	old=$(find "$T/b/frames" -name '*.png' ! -newermt '2002-01-01' | wc -l)
	[ "$old" -eq 3 ] || bad "$old of the 3 finished frames were left alone"
	# another quality: a new Makefile, every frame again
	run "$TL" "$REAL" 2024-10-13T14:00Z 2024-10-13T15:00Z $ARGS --noise-size 16 --no-video -o "$T/b" -- --quality medium
	expect_rc 0
	old=$(find "$T/b/frames" -name '*.png' ! -newermt '2002-01-01' | wc -l)
	[ "$old" -eq 0 ] || bad "$old frames kept after the options changed"
fi
end

begin timelapse_killed_leaves_only_whole_frames_and_a_rerun_completes
if [ ! -f "$REAL" ]; then
	skip timelapse_killed_leaves_only_whole_frames_and_a_rerun_completes "no $REAL (shared data absent)"
else
	# its own process group, so that the kill reaches make and its renders
	setsid "$TL" "$REAL" 2024-10-13T12:00Z 2024-10-13T16:00Z --size 48x27 --step 20m -j 2 \
		--no-video --noise "$T/noise.exr" -o "$T/c" >/dev/null 2>&1 &
	pid=$!
	n=0
	while [ $n -lt 100 ] && [ "$(ls "$T/c/frames" 2>/dev/null | grep -c '\.png$')" -lt 2 ]; do
		sleep 0.1; n=$((n + 1))
	done
	kill -TERM -- "-$pid" 2>/dev/null
	wait $pid 2>/dev/null
	for f in "$T"/c/frames/*; do
		[ -e "$f" ] || continue
		case $f in *.png) png_ok "$f" || bad "$(basename "$f") is not a whole PNG" ;;
		*) bad "left behind: $(basename "$f")" ;; esac
	done
	run "$TL" "$REAL" 2024-10-13T12:00Z 2024-10-13T16:00Z --size 48x27 --step 20m -j 2 \
		--no-video --noise "$T/noise.exr" -o "$T/c"
	expect_rc 0
	expect_only_files "$T/c/frames" 13
fi
end

begin timelapse_usage_errors
run "$TL"; expect_rc 2; expect_err "expected FILE FROM TO"
run "$TL" "$T/noise.exr" 2024-10-13T14:00Z 2024-10-13T15:00Z --step 7x; expect_rc 2; expect_err "--step"
run "$TL" "$T/noise.exr" 2024-10-13T15:00Z 2024-10-13T14:00Z; expect_rc 2; expect_err "is before FROM"
run "$TL" "$T/noise.exr" soon 2024-10-13T14:00Z; expect_rc 2; expect_err "FROM: 'soon'"
run "$TL" "$T/noise.exr" 2024-10-13T14:00Z 2024-10-13T15:00Z --fps 0; expect_rc 2; expect_err "--fps"
run "$TL" "$T/absent.json" 2024-10-13T14:00Z 2024-10-13T15:00Z -o "$T/d"; expect_rc 1; expect_err "absent.json"
run "$TL" --help; expect_rc 0; expect_out "Usage: timelapse"; expect_out "--fps"
end

begin timelapse_shorter_rerun_and_another_noise_size_remake_what_changed
if [ ! -f "$REAL" ]; then
	skip timelapse_shorter_rerun_and_another_noise_size_remake_what_changed "no $REAL (shared data absent)"
elif [ $have_ffmpeg -eq 0 ]; then
	skip timelapse_shorter_rerun_and_another_noise_size_remake_what_changed "ffmpeg is not installed"
else
	run "$TL" "$REAL" 2024-10-13T14:00Z 2024-10-13T14:40Z $ARGS --fps 5 --noise-size 16 -o "$T/b" -- $ROPTS
	expect_rc 0
	# a shorter range in the same folder: the video has its own frames only,
	# not the earlier run's third one still on disk
	run "$TL" "$REAL" 2024-10-13T14:00Z 2024-10-13T14:20Z $ARGS --fps 5 --noise-size 16 -o "$T/b" -- $ROPTS
	expect_rc 0
	nf=$(ffprobe -v error -count_frames -select_streams v:0 -show_entries stream=nb_read_frames \
		-of csv=p=0 "$T/b/timelapse.mp4")
	[ "$nf" = 2 ] || bad "the video of 2 times has $nf frames"
	exrheader "$T/b/noise.exr" | grep -q 'cloudscapeVolumeSize.*(16 16 16)' || bad "the noise is not 16^3"
	run "$TL" "$REAL" 2024-10-13T14:00Z 2024-10-13T14:20Z $ARGS --fps 5 --noise-size 32 -o "$T/b" -- $ROPTS
	expect_rc 0
	exrheader "$T/b/noise.exr" | grep -q 'cloudscapeVolumeSize.*(32 32 32)' ||
		bad "--noise-size 32 kept the old noise: $(exrheader "$T/b/noise.exr" | grep VolumeSize)"
fi
end

begin slurm_timelapse_stops_with_sbatch_s_status_when_it_refuses
if [ ! -f "$REAL" ]; then
	skip slurm_timelapse_stops_with_sbatch_s_status_when_it_refuses "no $REAL (shared data absent)"
else
	printf '#!/bin/sh\necho "sbatch: error: invalid partition specified: bogus" >&2\nexit 1\n' >"$T/fsb"
	chmod +x "$T/fsb"
	# the noise given, so the frames job is the first submitted
	SBATCH="$T/fsb" run "$TOP/scripts/slurm-timelapse" "$REAL" 2024-10-13T14:00Z \
		2024-10-13T14:20Z --step 20m --noise "$T/noise.exr" -o "$T/sl"
	expect_rc 1
	expect_err "sbatch failed"
	[ -s "$T/out" ] && bad "job ids printed though sbatch refused: $(cat "$T/out")"
fi
end
