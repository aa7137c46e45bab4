# cloudrender --device: the CPU by default; cuda where the build and the
# machine have it, else a clear reason and exit 1 (CI: no nvcc, no GPU).
. "$TOP/tests/tools/lib.sh"
plan 7
CR="$BIN/cloudrender"
FAST="--size 32x18 --quality low --noise-size 16 -q"

# the run with --device cuda wrote FILE, or exited 1 saying why there is
# no GPU and wrote nothing
rendered_or_said_why() {
	if [ "$rc" -eq 0 ]; then
		expect_file "$1"
	else
		expect_rc 1
		grep -Eq '^cloudrender: --device cuda: (built without CUDA: .+|no CUDA device: .+)$' "$T/err" ||
			bad "no reason given: $(head -c 300 "$T/err")"
		expect_no_file "$1"
	fi
}

begin device_cpu_is_the_default_and_renders_the_same_image
run "$CR" $FAST -o "$T/default.exr"
expect_rc 0
run "$CR" $FAST --device cpu -o "$T/cpu.exr"
expect_rc 0
cmp -s "$T/default.exr" "$T/cpu.exr" || bad "--device cpu differs from the default"
end

begin device_cuda_renders_or_says_why_and_exits_1
run "$CR" $FAST --device cuda -o "$T/gpu.png"
rendered_or_said_why "$T/gpu.png"
end

begin device_unknown_is_a_usage_error
run "$CR" $FAST --device gpu -o "$T/x.png"
expect_rc 2; expect_err "--device: 'gpu' is not cpu or cuda"
end

begin device_reference_integrator_renders_or_says_why_and_benchmarks_no_reference
run "$CR" $FAST --device cuda --integrator reference --spp 2 -o "$T/ref.exr"
rendered_or_said_why "$T/ref.exr"
run "$CR" $FAST --device cuda --integrator reference --device-bench 2 -o "$T/x.png"
expect_rc 2; expect_err "--device-bench times the march, not the reference integrator"
expect_no_file "$T/x.png"
end

begin device_adaptive_and_cone_marches_are_cpu_only
run "$CR" $FAST --device cuda --march adaptive -o "$T/x.png"
expect_rc 2; expect_err "the adaptive march runs on the CPU only"
expect_no_file "$T/x.png"
run "$CR" $FAST --device cuda --light-march cone -o "$T/x.png"
expect_rc 2; expect_err "the cone light march runs on the CPU only"
expect_no_file "$T/x.png"
run "$CR" $FAST --march adaptive --light-march cone -o "$T/cpu.png"
expect_rc 0; expect_file "$T/cpu.png"
grep -aq '"march":"adaptive","light_march":"cone"' "$T/cpu.png" ||
	bad "the metadata do not name the marches"
# the presets find the light at every other sample, on either device;
# --source-every 1 at every one
grep -aq '"source_every":2' "$T/cpu.png" || bad "the metadata do not name the preset's stride"
run "$CR" $FAST --source-every 1 -o "$T/cpu1.png"
expect_rc 0; expect_file "$T/cpu1.png"
grep -aq '"source_every":1' "$T/cpu1.png" || bad "the metadata do not name the source's stride"
end

begin device_bench_needs_cuda
run "$CR" $FAST --device-bench 3 -o "$T/x.png"
expect_rc 2; expect_err "--device-bench needs --device cuda"
expect_no_file "$T/x.png"
end

# The CPU's per-pixel kernels (lib/render/cpu/kernel.c: baseline x86-64,
# AVX2 and x86-64-v4, the best the processor has unless CLOUDSCAPE_KERNEL
# names one) give the same bits: the hard scenes' clouds, fog, a
# cumulonimbus, cirrus at dusk and terrain under cloud, EXR float
# (R G B A Z) compared whole; -v names the kernel that ran.
begin device_cpu_kernels_give_the_same_bits
if ! grep -qw avx2 /proc/cpuinfo 2>/dev/null; then
	skip device_cpu_kernels_give_the_same_bits "this processor has no AVX2: one kernel only"
else
	"$TOP/scripts/make-bern-dem" -r 400 "$T/dem.tif" >/dev/null 2>&1 &&
		"$BIN/terrainprep" -q "$T/dem.tif" -o "$T/bern.exr" || bad "no terrain"
	kernels="base avx2"
	v4=1 # x86-64-v4: these five AVX-512 parts (and AVX2)
	for f in avx512f avx512bw avx512cd avx512dq avx512vl; do
		grep -qw $f /proc/cpuinfo || v4=0
	done
	[ $v4 = 1 ] && kernels="$kernels avx512"
	for sc in fog-low-sun cumulonimbus-side cirrus-dusk terrain-broken inside-cloud; do
		args=$(sed "s|@TERRAIN@|$T/bern.exr|" "$TOP/tests/scenes/$sc.args")
		for k in $kernels; do
			# shellcheck disable=SC2086
			CLOUDSCAPE_KERNEL=$k "$CR" --wx "$TOP/tests/scenes/$sc.json" $args --size 64x36 \
				--quality medium --noise-size 32 -v --float -o "$T/$sc-$k.exr" 2>"$T/err" ||
				bad "$sc: $k failed"
			grep -q "rendered on the CPU: kernel $k\$" "$T/err" || bad "$sc: not the $k kernel"
			same_pixels "$T/$sc-base.exr" "$T/$sc-$k.exr" || bad "$sc: kernels base and $k differ"
		done
	done
fi
end
