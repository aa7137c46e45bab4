# Helpers for tool tests: each case prints "ok NAME" or "FAIL NAME: why".
# BIN is the folder of the built programs, TOP the source tree, HELPERS the
# built test helpers (tests/helpers/*.c), DATA the shared real-data folder
# (may be absent: tests that need it skip with a message).
#
# The plan: a script says how many cases it runs in ONE place, a line
#     plan N
# right after sourcing this file.  Each case prints exactly one line (end,
# skip or fail_case).  tests/run fails a script that prints no plan or a
# number of case lines other than N (it ended early, or a case was added
# without raising N).  Skips are only for the shared data folder ($DATA)
# being absent; a missing program or a helper that does not start is a FAIL.
: "${BIN:?BIN must name the folder of the built programs}"
BIN=$(cd "$BIN" && pwd)
T=$(mktemp -d "${TMPDIR:-/tmp}/cs-tool-test.XXXXXX")
trap 'chmod -R u+w "$T" 2>/dev/null; rm -rf "$T"' EXIT
case_name=""
case_bad=""
begin() { case_name=$1; case_bad=""; case_skipped=0; }
bad() { case_bad="${case_bad:+$case_bad; }$1"; }
# end: the case's line, unless it said skip (a skipped case has its line)
end() {
	if [ "${case_skipped:-0}" -eq 1 ]; then case_skipped=0; return; fi
	if [ -z "$case_bad" ]; then echo "ok $case_name"; else echo "FAIL $case_name: $case_bad"; fi
}
# run CMD...: runs it, keeping stdout in $T/out, stderr in $T/err, status in $rc
run() { "$@" >"$T/out" 2>"$T/err"; rc=$?; }
expect_rc() { [ "$rc" -eq "$1" ] || bad "exit status $rc, expected $1 (stderr: $(head -c 300 "$T/err"))"; }
expect_err() { grep -qF -- "$1" "$T/err" || bad "stderr lacks '$1' (got: $(head -c 300 "$T/err"))"; }
expect_out() { grep -qF -- "$1" "$T/out" || bad "stdout lacks '$1'"; }
expect_file() { [ -s "$1" ] || bad "no file $1"; }
expect_no_file() { [ ! -e "$1" ] || bad "file $1 should not exist"; }
# no temporaries left beside outputs in a folder
expect_only_files() { # dir count
	n=$(ls -A "$1" | wc -l)
	[ "$n" -eq "$2" ] || bad "$1 holds $n entries, expected $2: $(ls -A "$1" | tr '\n' ' ')"
}
# plan N: the number of cases this script runs (once, at its top)
plan() { echo "plan $1"; }
# fail_case NAME WHY: the case could not run here and that is an error
fail_case() { echo "FAIL $1: $2"; }
# skip NAME WHY: the case cannot run here (e.g. the shared data is absent)
skip() { echo "skip $1: $2"; case_skipped=1; }
# same_pixels A B: the two images hold the same pixels (PNG: the samples as
# pngtopnm decodes them; EXR: R G B A Z exactly), whatever their text chunks
# or attributes say; for "cmp -s A B && bad ..." where the outputs' metadata
# (cloudrender writes its settings) differs anyway.
same_pixels() {
	case $1 in
	*.exr) "$HELPERS/exrpixels" "$1" R G B A Z >"$T/.px1" && "$HELPERS/exrpixels" "$2" R G B A Z >"$T/.px2" ;;
	*) pngtopnm "$1" >"$T/.px1" && pngtopnm "$2" >"$T/.px2" ;;
	esac || { bad "cannot read the pixels of $1 or $2"; return 2; }
	cmp -s "$T/.px1" "$T/.px2"
}
