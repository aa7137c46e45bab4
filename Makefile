# cloudscape - build, test, install.
#
#   make              library and programs: build/libcloudscape.a, build/bin/*
#   make check        build and run every test (scripts/deps only when pkg-config
#                     or a tool the tests use is missing)
#   make check SAN=1  the same with AddressSanitizer + UBSan (in build-san/)
#   make check SAN=thread  unit tests and the threaded programs' scripts under
#                     ThreadSanitizer (in build-tsan/)
#   make check-all    check, check SAN=1 and check SAN=thread (what CI runs)
#   make WERROR=0     warnings stay warnings (the default, WERROR=1, for CI
#                     and developers, makes them errors)
#   make fuzz FUZZ_SECONDS=N  libFuzzer targets (tests/fuzz/) built with clang,
#                     ASan + UBSan, in build-fuzz/; each run N s (default 10)
#   make bench        benchmarks (not part of check)
#   make CUDA=1       also the GPU renderer (cloudrender --device cuda), built by
#                     nvcc (NVCC=, found on the PATH or at /usr/local/cuda/bin) into
#                     build-cuda/; without CUDA=1, --device cuda says why there is
#                     no GPU (lib/render/cuda/device_none.c; README: "The GPU renderer")
#   make check-gpu    on a machine with a GPU: CUDA=1, then scripts/gpu-check
#                     (CPU against GPU renders of tests/scenes, 1080p frames/s)
#   make study        the accuracy study: error against the reference integrator
#                     and time, per scene and setting (not part of check)
#   make mutate       the suite's mutation score (scripts/mutate, nice -n 19;
#                     not part of check: it rebuilds and runs it per mutant)
#   make demo         bake the noise, make a synthetic Bern terrain, render into out/,
#                     compare two renders of the capture an hour apart (skycompare),
#                     a short time-lapse of the capture (scripts/timelapse)
#   make install PREFIX=/usr/local DESTDIR=   programs, scripts, man pages,
#                     bash completion (BASHCOMPDIR: bash-completion's
#                     completionsdir under PREFIX, else
#                     PREFIX/share/bash-completion/completions)
#   make uninstall PREFIX=/usr/local DESTDIR=  removes what install put there
#   make deps         install the Debian packages the project needs
#   make clean

VERSION   := 0.1.0
PREFIX    ?= /usr/local
DESTDIR   ?=
SAN       ?=
WERROR    ?= 1
# every tools/*.c but the shared cli.c is a program
PROGRAMS  := $(filter-out cli,$(basename $(notdir $(wildcard tools/*.c))))
# the real meteoblue capture the demo's weather sheet draws (not ours)
CAPTURE   := ../shared/data/weather/meteoblue-basic-clouds-solar-1h.json
# the scripts users run, installed with the programs (each has a man page)
SCRIPTS   := genus-sheet quality-study radiation-study weather-sheet timelapse slurm-timelapse
# bash-completion's own directory rebased on PREFIX (bash-completion looks
# in PREFIX/share too), else the same path by hand
BASHCOMPDIR ?= $(or $(shell pkg-config --define-variable=prefix=$(PREFIX) \
		--variable=completionsdir bash-completion 2>/dev/null),$(PREFIX)/share/bash-completion/completions)
PKGS      := OpenEXR libpng libcjson libcurl gdal

CC        ?= cc
CFLAGS    ?= -O2 -g
WARN      := -Wall -Wextra $(if $(filter 1,$(WERROR)),-Werror) -Wshadow -Wpointer-arith -Wvla \
             -Wstrict-prototypes -Wmissing-prototypes -Wformat=2
comma     := ,
FUZZ_SECONDS ?= 10
FUZZ_CC   ?= clang
ifeq ($(FUZZ),1)
# the library and programs instrumented for libFuzzer (tests/fuzz/run)
B         := build-fuzz
CC        := $(FUZZ_CC)
SANFLAGS  := -fsanitize=fuzzer-no-link$(comma)address$(comma)undefined$(comma)float-cast-overflow \
             -fno-sanitize-recover=all -fno-omit-frame-pointer
else ifeq ($(SAN),thread)
B         := build-tsan
SANFLAGS  := -fsanitize=thread -fno-omit-frame-pointer
else ifneq ($(SAN),)
B         := build-san
SANFLAGS  := -fsanitize=address$(comma)undefined$(comma)float-cast-overflow -fno-sanitize-recover=all -fno-omit-frame-pointer
else
B         := build
SANFLAGS  :=
endif
# The GPU renderer (lib/render/cuda/): only with CUDA=1, into build-cuda/.
# Not by default although nvcc may be there: the unity build, compiled once
# for every effect and once for each of CUDA_KERNELS, takes minutes of nvcc,
# its objects would link the CUDA runtime into every test program (and under
# ASan and TSan), and CI has no GPU to run it.
CUDA      ?= 0
NVCC      ?= $(or $(shell command -v nvcc 2>/dev/null),$(wildcard /usr/local/cuda/bin/nvcc))
NVCC_ARCH ?= -gencode arch=compute_90,code=sm_90 -gencode arch=compute_90,code=compute_90
CUDA_LIB  ?= $(if $(NVCC),$(firstword $(wildcard $(dir $(NVCC))../lib64 $(dir $(NVCC))../lib)))
# what render_cuda.o keeps global (the rest of the unity build's host code
# is made local, so that it never meets the C objects at link time)
CUDA_API  := cs_device_available cs_cuda_scene_new cs_cuda_scene_update cs_cuda_scene_free cs_cuda_render cs_cuda_bench \
	     cs_cuda_kernel_name cs_cuda_reference
# the kernels for a set of effects (lib/render/cuda/kernels.h names the same):
# render_cuda.cu compiled again for each, its launch kept global
CUDA_KERNELS := plain terrain weather
ifeq ($(CUDA),1)
ifeq ($(NVCC),)
$(error CUDA=1 but nvcc is not on the PATH nor at /usr/local/cuda/bin/nvcc: give NVCC=)
endif
ifneq ($(SAN)$(FUZZ),)
$(error CUDA=1 does not combine with SAN or FUZZ)
endif
B         := build-cuda
DEVICE_OBJ = $(B)/lib/render/cuda/render_cuda.o $(CUDA_KERNELS:%=$(B)/lib/render/cuda/render_cuda_%.o)
CUDA_LIBS  = -L$(CUDA_LIB) -lcudart_static -ldl -lrt -lstdc++
else
DEVICE_OBJ = $(B)/lib/render/cuda/device_none.o
CUDA_LIBS  =
CUDA_WHY  := $(if $(NVCC),built without CUDA: this build was made without CUDA=1 (nvcc is at $(NVCC)); \
		build with make CUDA=1,built without CUDA: nvcc was not found at build time)
endif
# programs the tool tests run (scripts/deps installs them: gdal-bin, netpbm, jq,
# openexr, man-db, ffmpeg, python3, munge, slurmctld, slurmd, slurm-client)
TEST_TOOLS := gdal_translate gdalinfo gdallocationinfo gdalwarp pamenlarge pnmcat pnmpad \
              pamsumm pnmpsnr pnmtoplainpnm pnmtopng pngtopnm ppmtoppm jq exrheader man \
              ffmpeg ffprobe python3 gdal_create munged slurmctld slurmd sbatch
PKG_CFLAGS = $(shell pkg-config --cflags $(PKGS))
PKG_LIBS   = $(shell pkg-config --libs $(PKGS))
ALL_CFLAGS = -std=c17 -D_POSIX_C_SOURCE=200809L -DCS_VERSION='"$(VERSION)"' \
             $(WARN) $(CFLAGS) $(SANFLAGS) -pthread -iquote lib -iquote tools $(PKG_CFLAGS) -MMD -MP
LDLIBS     = $(if $(filter 1,$(CUDA)),-Wl$(comma)--as-needed) $(PKG_LIBS) $(CUDA_LIBS) -lm -pthread

LIB_SRC   := $(wildcard lib/*/*.c)
# the per-pixel loop as one translation unit, for baseline x86-64, AVX2 and
# x86-64-v4 (AVX-512: the same operations, with its 32 vector registers)
KERNELS    := base avx2 avx512
KERNEL_OBJ := $(KERNELS:%=$(B)/lib/render/cpu/kernel_%.o)
KERNEL_ISA_base   :=
KERNEL_ISA_avx2   := -mavx2
KERNEL_ISA_avx512 := -march=x86-64-v4
LIB_OBJ   := $(LIB_SRC:lib/%.c=$(B)/lib/%.o) $(DEVICE_OBJ) $(KERNEL_OBJ)
CLI_OBJ   := $(B)/tools/cli.o
BINS      := $(PROGRAMS:%=$(B)/bin/%)
UNIT_SRC  := $(wildcard tests/unit/test_*.c)
UNIT_BINS := $(UNIT_SRC:tests/unit/%.c=$(B)/tests/%)
# test helpers (servers, generators): tests/helpers/*.c -> $(B)/tests/helpers/*
HELP_SRC  := $(wildcard tests/helpers/*.c)
HELP_BINS := $(HELP_SRC:tests/helpers/%.c=$(B)/tests/helpers/%)
# libFuzzer targets: tests/fuzz/fuzz_*.c -> build-fuzz/fuzz/fuzz_*
FUZZ_SRC  := $(wildcard tests/fuzz/fuzz_*.c)
FUZZ_BINS := $(FUZZ_SRC:tests/fuzz/%.c=$(B)/fuzz/%)

.SECONDARY:
# the accuracy study's tools: bench/*.c -> $(B)/bench/*
BENCH_SRC := $(wildcard bench/*.c)
BENCH_BINS := $(BENCH_SRC:bench/%.c=$(B)/bench/%)

.PHONY: check-gpu
.PHONY: all check check-all check-run tests bench study mutate demo install uninstall deps have-deps clean \
	fuzz fuzz-build
all: $(B)/libcloudscape.a $(BINS)

$(B)/lib/%.o: lib/%.c
	@mkdir -p $(@D)
	$(CC) $(ALL_CFLAGS) -c $< -o $@
# the GPU renderer's one translation unit (CUDA=1); nvcc's and the host
# compiler's -Wall warnings are errors (not -Wextra: C designated initializers
# compiled as C++ would warn of every member left out),
# but 20091 (a CS_CONST table read in the host copy of a CS_HD function: that
# copy is never called, the CPU renders with the C objects)
NVCC_FLAGS = -std=c++17 -O3 $(NVCC_ARCH) -D_POSIX_C_SOURCE=200809L -DCS_VERSION='"$(VERSION)"' \
	     -I lib -Werror all-warnings -diag-suppress 20091 -Xcompiler -Wall
$(B)/lib/render/cuda/render_cuda.o: lib/render/cuda/render_cuda.cu
	@mkdir -p $(@D)
	$(NVCC) $(NVCC_FLAGS) -MMD -MP -MT $@ -MF $(@:.o=.d) -c $< -o $@.tmp
	objcopy $(CUDA_API:%=-G %) $@.tmp $@
	@rm -f $@.tmp
$(CUDA_KERNELS:%=$(B)/lib/render/cuda/render_cuda_%.o): $(B)/lib/render/cuda/render_cuda_%.o: \
		lib/render/cuda/render_cuda.cu
	@mkdir -p $(@D)
	$(NVCC) $(NVCC_FLAGS) -DCS_CUDA_KERNEL=$* -MMD -MP -MT $@ -MF $(@:.o=.d) -c $< -o $@.tmp
	objcopy -G cs_cuda_texture_$* -G cs_cuda_launch_$* $@.tmp $@
	@rm -f $@.tmp
# lib/render/cpu/kernel.c three times: -O3, no contraction (the same bits as
# the library's objects), for each instruction set; only the kernel's
# functions kept global
$(KERNEL_OBJ): $(B)/lib/render/cpu/kernel_%.o: lib/render/cpu/kernel.c
	@mkdir -p $(@D)
	$(CC) $(ALL_CFLAGS) -O3 -ffp-contract=off -fno-math-errno $(KERNEL_ISA_$*) \
		-DCS_KERNEL=cs_kernel_rows_$* -DCS_KERNEL_EXTINCTION=cs_kernel_extinction_$* \
		-MT $@ -MF $(@:.o=.d) -c $< -o $@.tmp
	objcopy -G cs_kernel_rows_$* -G cs_kernel_extinction_$* $@.tmp $@
	@rm -f $@.tmp
$(B)/lib/render/cuda/device_none.o: ALL_CFLAGS += -DCS_CUDA_WHY='"$(CUDA_WHY)"'
# the texture unit's ceiling for the noise's lookups (make check-gpu)
$(B)/bench/texfetch: bench/texfetch.cu
	@mkdir -p $(@D)
	$(NVCC) -O3 $(NVCC_ARCH) -Werror all-warnings $< -o $@
# the baker's row loops vectorized (-O3; no contraction: the same bits)
$(B)/lib/noise/noise.o $(B)/lib/noise/volume.o: ALL_CFLAGS += -O3 -ffp-contract=off
# the fog's orders of scattering (lib/render/fog.c): dot products, vectorized
$(B)/lib/render/fog.o: ALL_CFLAGS += -O3 -ffp-contract=off
# ... and, under ThreadSanitizer, not instrumented: its instrumented loops
# took test_render from 26 to 246 s there (the light fields of the random
# scenes' broken layers), the TSan stage's longest.  Its threads (the pool's
# tasks, cs_fog_solve_n) each write their own mode and colour of the
# fields and their own solver; the pool's hand-over is instrumented, and
# the solver built instrumented ran cs_fog_solve_n on 5 threads clean
ifeq ($(SAN),thread)
$(B)/lib/render/fog.o: ALL_CFLAGS += -fno-sanitize=thread
endif
$(B)/tools/%.o: tools/%.c
	@mkdir -p $(@D)
	$(CC) $(ALL_CFLAGS) -c $< -o $@
$(B)/tests/%.o: tests/unit/%.c
	@mkdir -p $(@D)
	$(CC) $(ALL_CFLAGS) -iquote tests/unit -c $< -o $@

$(B)/bench/%.o: bench/%.c
	@mkdir -p $(@D)
	$(CC) $(ALL_CFLAGS) -c $< -o $@
$(B)/bench/%: $(B)/bench/%.o $(B)/libcloudscape.a
	$(CC) $(CFLAGS) $(SANFLAGS) -o $@ $^ $(LDLIBS)

$(B)/tests/helpers/%.o: tests/helpers/%.c
	@mkdir -p $(@D)
	$(CC) $(ALL_CFLAGS) -c $< -o $@
$(B)/tests/helpers/%: $(B)/tests/helpers/%.o $(B)/libcloudscape.a
	$(CC) $(CFLAGS) $(SANFLAGS) -o $@ $^ $(LDLIBS)

$(B)/fuzz/%.o: tests/fuzz/%.c
	@mkdir -p $(@D)
	$(CC) $(ALL_CFLAGS) -c $< -o $@
$(B)/fuzz/fuzz_%: $(B)/fuzz/fuzz_%.o $(B)/libcloudscape.a
	$(CC) $(CFLAGS) $(subst fuzzer-no-link,fuzzer,$(SANFLAGS)) -o $@ $^ $(LDLIBS)

$(B)/libcloudscape.a: $(LIB_OBJ)
	@rm -f $@
	$(AR) rcs $@ $^
$(B)/bin/%: $(B)/tools/%.o $(CLI_OBJ) $(B)/libcloudscape.a
	@mkdir -p $(@D)
	$(CC) $(CFLAGS) $(SANFLAGS) -o $@ $^ $(LDLIBS)
$(B)/tests/test_%: $(B)/tests/test_%.o $(B)/libcloudscape.a
	$(CC) $(CFLAGS) $(SANFLAGS) -o $@ $^ $(LDLIBS)

tests: all $(UNIT_BINS) $(HELP_BINS) $(BENCH_BINS)

# check installs what is missing first (only then: no dpkg or apt-get when
# everything is there), then re-enters make so that pkg-config sees the
# freshly installed packages.
check: have-deps
	@$(MAKE) --no-print-directory tests
	@$(if $(filter thread,$(SAN)),TSAN_OPTIONS="suppressions=$(CURDIR)/tests/tsan.supp $$TSAN_OPTIONS" \
		SCRIPTS="$(TSAN_SCRIPTS)") tests/run $(B)

# Under ThreadSanitizer: every unit binary, and the tool scripts of the
# programs that run the thread pool (noise baking, frame rendering, the
# reference); the other programs are single-threaded and gain nothing.
# test_reference leaves its three slowest comparisons with the path tracer
# to the plain and ASan runs there (t_under_tsan; their threads are run by
# other cases): alone on the 2-core machine it took 283 s with them, 57 s
# without (544 s in CI, beside the other binaries).
TSAN_SCRIPTS := cloudrender noisebake reference render_info

check-all:
	@$(MAKE) --no-print-directory check
	@$(MAKE) --no-print-directory check SAN=1
	@$(MAKE) --no-print-directory check SAN=thread

have-deps:
	@if command -v pkg-config >/dev/null 2>&1 && pkg-config --exists $(PKGS) && \
	    (for t in $(TEST_TOOLS); do command -v $$t >/dev/null 2>&1 || exit 1; done); \
	then :; else scripts/deps; fi

deps:
	@scripts/deps

# the GPU renderer against the CPU's, and its speed (scripts/gpu-check), on a
# machine with a GPU (CI has none: never part of check)
check-gpu: have-deps
	@$(MAKE) --no-print-directory CUDA=1 all build-cuda/bench/imgerr build-cuda/bench/texfetch
	@scripts/gpu-check --build build-cuda $(GPU_CHECK_ARGS)

# the accuracy study (scripts/accuracy-study): STUDY_ARGS=--full for 1280x720
study: have-deps all $(BENCH_BINS)
	@scripts/accuracy-study --build $(B) $(STUDY_ARGS)

# the fuzz build (FUZZ=1: build-fuzz/), then every target FUZZ_SECONDS s
fuzz: have-deps
	@[ -f "$$($(FUZZ_CC) -print-runtime-dir 2>/dev/null)/libclang_rt.fuzzer-x86_64.a" ] || scripts/deps
	@$(MAKE) --no-print-directory FUZZ=1 fuzz-build
	@tests/fuzz/run build-fuzz $(FUZZ_SECONDS)

fuzz-build: all $(FUZZ_BINS)

bench: have-deps
	@$(MAKE) --no-print-directory all $(BENCH_BINS)
	@scripts/bench $(B)

mutate: have-deps
	nice -n 19 scripts/mutate

demo: have-deps
	@$(MAKE) --no-print-directory all
	@mkdir -p out
	$(B)/bin/noisebake -o out/noise.exr --preview out/noise-preview.png
	scripts/make-bern-dem out/bern-synthetic-dem.tif
	$(B)/bin/terrainprep out/bern-synthetic-dem.tif -o out/bern.exr --hillshade out/bern-hillshade.png
	$(B)/bin/cloudrender --noise out/noise.exr --size 1280x720 -o out/demo.png -o out/demo.exr
	$(B)/bin/cloudrender --noise out/noise.exr --terrain out/bern.exr --view gurten \
		--time 2021-06-14T16:45Z --size 1280x720 -o out/gurten.png
	CLOUDRENDER=$(B)/bin/cloudrender scripts/genus-sheet out/genus-sheet.png --noise out/noise.exr
	@if [ -f $(CAPTURE) ]; then \
		echo "CLOUDRENDER=$(B)/bin/cloudrender WXINTERP=$(B)/bin/wxinterp scripts/weather-sheet $(CAPTURE) 2024-10-07 out/weather-sheet.png --noise out/noise.exr"; \
		CLOUDRENDER=$(B)/bin/cloudrender WXINTERP=$(B)/bin/wxinterp scripts/weather-sheet \
			$(CAPTURE) 2024-10-07 out/weather-sheet.png --noise out/noise.exr; \
	else echo "demo: $(CAPTURE) is absent: no weather sheet"; fi
	@if [ -f $(CAPTURE) ]; then \
		for h in 14 15; do \
			echo "$(B)/bin/wxinterp $(CAPTURE) --at 2024-10-13T$${h}:00Z | $(B)/bin/cloudrender --wx - --noise out/noise.exr -o out/sky-$${h}h.png -o out/sky-$${h}h.exr"; \
			$(B)/bin/wxinterp $(CAPTURE) --at 2024-10-13T$${h}:00Z | \
			$(B)/bin/cloudrender -q --wx - --noise out/noise.exr \
				-o out/sky-$${h}h.png -o out/sky-$${h}h.exr || exit 1; \
		done; \
		echo "$(B)/bin/skycompare out/sky-14h.exr out/sky-15h.exr -o out/skycompare-side.png --overlay out/skycompare-overlay.png --diff out/skycompare-diff.png"; \
		$(B)/bin/skycompare out/sky-14h.exr out/sky-15h.exr -o out/skycompare-side.png \
			--overlay out/skycompare-overlay.png --diff out/skycompare-diff.png; \
	else echo "demo: $(CAPTURE) is absent: no sky comparison"; fi
	@if [ -f $(CAPTURE) ]; then \
		echo "scripts/timelapse $(CAPTURE) 2024-10-13T12:00Z 2024-10-13T18:00Z --step 20m --size 320x180 --fps 6 --noise out/noise.exr -o out/timelapse -- --quality low"; \
		WXINTERP=$(B)/bin/wxinterp CLOUDRENDER=$(B)/bin/cloudrender NOISEBAKE=$(B)/bin/noisebake \
		scripts/timelapse $(CAPTURE) 2024-10-13T12:00Z 2024-10-13T18:00Z --step 20m \
			--size 320x180 --fps 6 --noise out/noise.exr -o out/timelapse -- --quality low || exit 1; \
	else echo "demo: $(CAPTURE) is absent: no time-lapse"; fi
	@echo "demo: wrote out/demo.png and out/demo.exr (the default scene), out/gurten.png (from the"
	@echo "demo: Gurten over a SYNTHETIC Bern terrain), out/genus-sheet.png, out/noise.exr,"
	@echo "demo: out/noise-preview.png, out/bern.exr and out/bern-hillshade.png, and"
	@echo "demo: out/weather-sheet.png (a rainy overcast day of the real meteoblue capture),"
	@echo "demo: out/sky-14h.png and out/sky-15h.png (the capture's 2024-10-13 at 14:00 and"
	@echo "demo: 15:00 UTC) and out/skycompare-side.png, -overlay.png, -diff.png (the two compared),"
	@echo "demo: out/timelapse/timelapse.mp4 (the capture's 2024-10-13 from 12:00 to 18:00 UTC, a"
	@echo "demo: frame every 20 minutes, from out/timelapse/frames/*.png; make -C out/timelapse resumes it)"

MAN1 := $(PROGRAMS:%=man/%.1) $(SCRIPTS:%=man/%.1)
MAN5 := $(wildcard man/*.5)
install: all
	install -d $(DESTDIR)$(PREFIX)/bin $(DESTDIR)$(PREFIX)/share/man/man1 \
		$(DESTDIR)$(PREFIX)/share/man/man5 $(DESTDIR)$(BASHCOMPDIR)
	install -m 755 $(BINS) $(SCRIPTS:%=scripts/%) $(DESTDIR)$(PREFIX)/bin/
	install -m 644 $(MAN1) $(DESTDIR)$(PREFIX)/share/man/man1/
	install -m 644 $(MAN5) $(DESTDIR)$(PREFIX)/share/man/man5/
	for p in $(PROGRAMS) $(SCRIPTS); do \
		install -m 644 completion/cloudscape.bash $(DESTDIR)$(BASHCOMPDIR)/$$p || exit 1; \
	done

uninstall:
	rm -f $(addprefix $(DESTDIR)$(PREFIX)/bin/,$(PROGRAMS) $(SCRIPTS)) \
		$(addprefix $(DESTDIR)$(PREFIX)/share/man/man1/,$(notdir $(MAN1))) \
		$(addprefix $(DESTDIR)$(PREFIX)/share/man/man5/,$(notdir $(MAN5))) \
		$(addprefix $(DESTDIR)$(BASHCOMPDIR)/,$(PROGRAMS) $(SCRIPTS))

clean:
	rm -rf build build-san build-tsan build-fuzz build-cuda out

-include $(LIB_OBJ:.o=.d) $(CLI_OBJ:.o=.d) $(PROGRAMS:%=$(B)/tools/%.d) \
	$(UNIT_SRC:tests/unit/%.c=$(B)/tests/%.d) $(HELP_SRC:tests/helpers/%.c=$(B)/tests/helpers/%.d) \
	$(FUZZ_SRC:tests/fuzz/%.c=$(B)/fuzz/%.d) $(BENCH_SRC:bench/%.c=$(B)/bench/%.d)
