# cloudrender's cache of the noise it bakes in memory: what a run reads
# from it is what baking gives (the expectation: a run with the cache off),
# it lives where XDG says, a damaged or foreign file is baked anew, and it
# can be turned off.
. "$TOP/tests/tools/lib.sh"
plan 4
CR="$BIN/cloudrender"
FAST="--size 48x27 --quality low --noise-size 24 -q"

begin noise_cache_gives_the_baked_volume_bit_for_bit
CLOUDSCAPE_NO_CACHE=1 XDG_CACHE_HOME="$T/x" "$CR" $FAST -o "$T/baked.exr" 2>"$T/err" || bad "bake run failed"
[ ! -e "$T/x" ] || bad "CLOUDSCAPE_NO_CACHE=1 wrote a cache: $(ls -R "$T/x")"
XDG_CACHE_HOME="$T/x" "$CR" $FAST -o "$T/first.exr" 2>"$T/err" || bad "first run failed"
n=$(ls "$T/x/cloudscape" 2>/dev/null | grep -c '^noise-24x24x24-.*\.bin$')
[ "$n" -eq 1 ] || bad "expected one cached 24^3 volume, found: $(ls -A "$T/x/cloudscape" 2>&1)"
XDG_CACHE_HOME="$T/x" "$CR" $FAST -o "$T/second.exr" 2>"$T/err" || bad "second run failed"
cmp -s "$T/baked.exr" "$T/first.exr" || bad "the run that filled the cache differs from a bake"
cmp -s "$T/baked.exr" "$T/second.exr" || bad "the run that read the cache differs from a bake"
end

begin noise_cache_defaults_to_home_dot_cache
mkdir -p "$T/home"
env -u XDG_CACHE_HOME HOME="$T/home" "$CR" $FAST -o "$T/h.exr" 2>"$T/err" || bad "run failed"
ls "$T/home/.cache/cloudscape" 2>/dev/null | grep -q '^noise-24x24x24-' || bad "nothing in ~/.cache/cloudscape"
end

begin noise_cache_damaged_file_is_baked_anew
f=$(ls "$T/x/cloudscape"/noise-24x24x24-*.bin | head -n 1)
# flip bytes in the volume data: the checksum no longer matches
printf 'XXXXXXXX' | dd of="$f" bs=1 seek=4000 conv=notrunc 2>/dev/null
XDG_CACHE_HOME="$T/x" "$CR" $FAST -o "$T/third.exr" 2>"$T/err" || bad "run failed"
cmp -s "$T/baked.exr" "$T/third.exr" || bad "a damaged cache file was used"
# and it was rewritten whole: a fourth run reads it and still agrees
XDG_CACHE_HOME="$T/x" "$CR" $FAST -o "$T/fourth.exr" 2>"$T/err" || bad "run failed"
cmp -s "$T/baked.exr" "$T/fourth.exr" || bad "the rewritten cache file differs"
: >"$f" # truncated
XDG_CACHE_HOME="$T/x" "$CR" $FAST -o "$T/fifth.exr" 2>"$T/err" || bad "run failed"
cmp -s "$T/baked.exr" "$T/fifth.exr" || bad "a truncated cache file was used"
end

begin noise_cache_concurrent_runs_agree
rm -rf "$T/y"
for i in 1 2 3 4; do
	XDG_CACHE_HOME="$T/y" "$CR" $FAST --noise-size 28 -o "$T/c$i.exr" 2>"$T/err$i" &
done
wait
CLOUDSCAPE_NO_CACHE=1 "$CR" $FAST --noise-size 28 -o "$T/c0.exr" 2>/dev/null || bad "bake run failed"
for i in 1 2 3 4; do cmp -s "$T/c0.exr" "$T/c$i.exr" || bad "run $i differs"; done
# whole files only: no temporaries left beside the one volume
expect_only_files "$T/y/cloudscape" 1
end
