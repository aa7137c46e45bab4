# noisebake as a user runs it.
. "$TOP/tests/tools/lib.sh"
plan 9
NB="$BIN/noisebake"

begin noisebake_writes_volume_and_preview
run "$NB" -s 16 -d 8 -o "$T/n.exr" --preview "$T/p.png" -q
expect_rc 0; expect_file "$T/n.exr"; expect_file "$T/p.png"
run "$NB" --info "$T/n.exr"
expect_rc 0; expect_out "size: 16 x 16 x 8"; expect_out "seed: 0"
expect_out "recipe: R=perlin-worley:4:4:3;G=worley-fbm:4:3;B=worley-fbm:8:3;A=worley-fbm:16:3;gain=0.5"
head -c 8 "$T/p.png" | od -An -tx1 | grep -q '89 50 4e 47 0d 0a 1a 0a' || bad "preview is not a PNG"
end

begin noisebake_options_reach_the_file
run "$NB" -s 12 --depth 6 --seed 99 --freq 2,3,4,5 --octaves 1,2,3,4 \
	--worley-octaves 2 --gain 0.7 --float -t 2 -o "$T/o.exr"
expect_rc 0
run "$NB" --info "$T/o.exr"
expect_out "size: 12 x 12 x 6"; expect_out "seed: 99"
expect_out "recipe: R=perlin-worley:2:1:2;G=worley-fbm:3:2;B=worley-fbm:4:3;A=worley-fbm:5:4;gain=0.7"
expect_out "  B:"; expect_out "    period: 4 x 4 x 2 cells"
end

begin noisebake_output_bytes_do_not_depend_on_threads
run "$NB" -s 16 -t 1 -o "$T/t1.exr"; expect_rc 0
run "$NB" -s 16 -t 3 -o "$T/t3.exr"; expect_rc 0
cmp -s "$T/t1.exr" "$T/t3.exr" || bad "1 and 3 threads differ"
run "$NB" -s 16 --seed 1 -o "$T/s1.exr"; expect_rc 0
cmp -s "$T/t1.exr" "$T/s1.exr" && bad "a different seed gave the same bytes"
end

begin noisebake_writes_to_stdout
run "$NB" -s 8 -o -
expect_rc 0
cmp -s "$T/out" /dev/null && bad "nothing on stdout"
cp "$T/out" "$T/stdout.exr"
run "$NB" --info "$T/stdout.exr"; expect_rc 0; expect_out "size: 8 x 8 x 8"
run "$NB" -s 8 -o - --preview -; expect_rc 2; expect_err "cannot both use standard output"
end

begin noisebake_preview_slices_and_channels
run "$NB" -s 8 -d 4 --preview "$T/s.png" --slices 0,3 --channels RA
expect_rc 0; expect_file "$T/s.png"
# 2 slices of 8 + 2 gap = 18 wide; 2 channels = 18 high (PNG IHDR)
dims=$(od -An -tu1 -j16 -N8 "$T/s.png" | tr -s ' ')
[ "$dims" = " 0 0 0 18 0 0 0 18" ] || bad "preview size bytes '$dims'"
end

begin noisebake_bad_options_are_usage_errors
for args in "-s 1 -o x.exr" "-s 2000 -o x.exr" "-s abc -o x.exr" "-d 0 -o x.exr" \
	"--seed -1 -o x.exr" "--seed 2147483648 -o x.exr" "--freq 0 -o x.exr" \
	"--freq 1,2,3 -o x.exr" "--freq 1,2,3,4,5 -o x.exr" "--octaves 13 -o x.exr" \
	"--worley-octaves 0 -o x.exr" "--gain 0 -o x.exr" "--gain 1.5 -o x.exr" \
	"--gain nan -o x.exr" "-t 0 -o x.exr" "--channels RX -o x.exr" \
	"--channels RGBAR -o x.exr" "-s 8 --slices 8 --preview p.png" \
	"--slices , --preview p.png" "--bogus" "" "extra -o x.exr" \
	"--info a.exr -o b.exr" "-o x.png" "--preview p.exr"; do
	# shellcheck disable=SC2086
	(cd "$T" && "$NB" $args >"$T/out" 2>"$T/err"); rc=$?
	[ "$rc" -eq 2 ] || bad "'$args' exited $rc, expected 2"
	grep -q '^noisebake: \|^Try ' "$T/err" || bad "'$args' gave no 'noisebake:' message"
done
[ ! -e "$T/x.exr" ] || bad "a usage error left x.exr"
end

begin noisebake_help_and_version
run "$NB" --help; expect_rc 0; expect_out "Usage: noisebake"
for o in --output --size --depth --seed --freq --octaves --worley-octaves --gain \
	--float --threads --preview --slices --channels --info --quiet --verbose \
	--help --version; do
	grep -q -- "$o" "$T/out" || bad "--help lacks $o"
	grep -q -- "Fl ${o#-}" "$TOP/man/noisebake.1" || bad "man page lacks $o"
done
run "$NB" --version; expect_rc 0; expect_out "noisebake (cloudscape)"
end

begin noisebake_unwritable_output_leaves_nothing
mkdir "$T/ro"; echo keep >"$T/ro/n.exr"; chmod 555 "$T/ro"
if [ -w "$T/ro" ]; then
	# root ignores permissions: use a path whose folder does not exist
	run "$NB" -s 8 -o "$T/missing/n.exr"
	expect_rc 1; expect_err "noisebake: cannot create $T/missing/n.exr"
	expect_no_file "$T/missing"
else
	run "$NB" -s 8 -o "$T/ro/n.exr"
	expect_rc 1; expect_err "noisebake: cannot create"
	[ "$(cat "$T/ro/n.exr")" = keep ] || bad "existing file clobbered"
	expect_only_files "$T/ro" 1
fi
chmod 755 "$T/ro"
# a device is written in place, never replaced: /dev/full fails every write
if [ -c /dev/full ]; then
	run "$NB" -s 8 -o /dev/full
	expect_rc 1; expect_err "noisebake: cannot write /dev/full: No space left on device"
	[ -c /dev/full ] || bad "/dev/full is no longer a device"
fi
end

begin noisebake_info_reports_corrupt_input
run "$NB" -s 8 -o "$T/good.exr"; expect_rc 0
head -c 500 "$T/good.exr" >"$T/trunc.exr"
run "$NB" --info "$T/trunc.exr"; expect_rc 1; expect_err "noisebake: $T/trunc.exr:"
printf 'not an exr' >"$T/text.exr"
run "$NB" --info "$T/text.exr"; expect_rc 1; expect_err "not a readable OpenEXR file"
run "$NB" --info "$T/nope.exr"; expect_rc 1; expect_err "No such file"
run "$NB" --info - <"$T/good.exr"; expect_rc 0; expect_out "size: 8 x 8 x 8"
end
