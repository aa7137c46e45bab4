# cloudrender --device: the CPU by default; cuda where the build and the
# machine have it, else a clear reason and exit 1 (CI: no nvcc, no GPU).
. "$TOP/tests/tools/lib.sh"
plan 5
CR="$BIN/cloudrender"
FAST="--size 32x18 --quality low --noise-size 16 -q"

begin device_cpu_is_the_default_and_renders_the_same_image
run "$CR" $FAST -o "$T/default.exr"
expect_rc 0
run "$CR" $FAST --device cpu -o "$T/cpu.exr"
expect_rc 0
cmp -s "$T/default.exr" "$T/cpu.exr" || bad "--device cpu differs from the default"
end

begin device_cuda_renders_or_says_why_and_exits_1
run "$CR" $FAST --device cuda -o "$T/gpu.png"
if [ "$rc" -eq 0 ]; then
	expect_file "$T/gpu.png"
else
	expect_rc 1
	grep -Eq '^cloudrender: --device cuda: (built without CUDA: .+|no CUDA device: .+)$' "$T/err" ||
		bad "no reason given: $(head -c 300 "$T/err")"
	expect_no_file "$T/gpu.png"
fi
end

begin device_unknown_is_a_usage_error
run "$CR" $FAST --device gpu -o "$T/x.png"
expect_rc 2; expect_err "--device: 'gpu' is not cpu or cuda"
end

begin device_reference_integrator_is_cpu_only
run "$CR" $FAST --device cuda --integrator reference -o "$T/x.png"
expect_rc 2; expect_err "the reference integrator runs on the CPU only"
end

begin device_bench_needs_cuda
run "$CR" $FAST --device-bench 3 -o "$T/x.png"
expect_rc 2; expect_err "--device-bench needs --device cuda"
expect_no_file "$T/x.png"
end
