# The small conventions, as a user meets them: bash completion that knows
# every option, man pages without warnings, the scripts' --help and man
# pages, make install and make uninstall.
. "$TOP/tests/tools/lib.sh"
plan 4
PROGS="cloudrender mbfetch noisebake terrainprep wxinterp"
SCRIPTS="genus-sheet quality-study radiation-study weather-sheet timelapse slurm-timelapse"
COMP="$TOP/completion/cloudscape.bash"
have() { command -v "$1" >/dev/null 2>&1; }
# complete WORD...: what the completion offers for the last word, one a line
complete_words() {
	PATH="$BIN:$PATH" bash -c '. "$1"; shift; COMP_WORDS=("$@"); COMP_CWORD=$(($# - 1))
		_cloudscape "$1"; printf "%s\n" "${COMPREPLY[@]}"' sh "$COMP" "$@"
}

begin completion_offers_every_option_of_the_help_and_the_man_page
if have bash; then
	for p in $PROGS; do
		complete_words "$p" - >"$T/offered"
		# the options --help lists (the option column) and the man page's
		"$BIN/$p" --help | grep -E '^ +-' | grep -oE -- '--[a-z][a-z0-9-]*' | sort -u >"$T/help"
		grep '^\.It' "$TOP/man/$p.1" | grep -oE 'Fl -[a-z][a-z0-9-]*' | sed 's/^Fl /-/' |
			sort -u >"$T/man"
		[ -s "$T/help" ] || bad "$p --help lists no options"
		[ -s "$T/man" ] || bad "$p(1) lists no options"
		for o in $(cat "$T/help" "$T/man" | sort -u); do
			grep -qxF -- "$o" "$T/offered" || bad "$p: the completion lacks $o"
		done
	done
	# an option's value: the words offered are the ones the program takes
	# (each checked by the program, which refuses a bogus one)
	for c in "cloudrender --quality" "cloudrender --projection" "cloudrender --view" \
		"cloudrender -of" "cloudrender --cloud-depth" "cloudrender --sky-level" \
		"cloudrender --march" \
		"cloudrender --light-march" "cloudrender --integrator" "cloudrender --heap-towers" "cloudrender --deck-lattice" "cloudrender --ground-sky" \
		"terrainprep --format" "terrainprep --fill" \
		"mbfetch --provider" "mbfetch --site"; do
		set -- $c
		complete_words "$1" "$2" "" >"$T/values"
		[ -s "$T/values" ] || bad "'$c' completes to nothing"
		"$BIN/$1" "$2" bogus --help >/dev/null 2>&1 && bad "$c bogus is accepted"
		while read -r v; do
			"$BIN/$1" "$2" "$v" --help >/dev/null 2>&1 || bad "'$c' offers '$v', which $1 refuses"
		done <"$T/values"
	done
	# the scripts pass cloudrender's options on
	PATH="$TOP/scripts:$PATH" complete_words genus-sheet --qual >"$T/values"
	grep -qx -- --quality "$T/values" || bad "genus-sheet does not complete cloudrender's --quality"
	complete_words cloudrender --quality= >"$T/values"
	grep -qx medium "$T/values" || bad "--quality= does not complete the value"
	# a file where a file goes
	: >"$T/frame-xyz.png"
	complete_words cloudrender -o "$T/frame-x" | grep -qxF "$T/frame-xyz.png" ||
		bad "-o does not complete file names"
	end
else
	skip completion_offers_every_option_of_the_help_and_the_man_page "bash is missing"
fi

begin man_pages_have_no_warnings
if have man && have groff; then
	n=0
	for f in "$TOP"/man/*.[15]; do
		n=$((n + 1))
		w=$(MANWIDTH=80 man --warnings -l "$f" 2>&1 >/dev/null)
		[ -z "$w" ] || bad "man --warnings $(basename "$f"): $w"
		w=$(groff -t -ww -mandoc -Tutf8 -z "$f" 2>&1)
		[ -z "$w" ] || bad "groff -ww $(basename "$f"): $w"
	done
	[ "$n" -ge 11 ] || bad "only $n man pages"
	end
else
	skip man_pages_have_no_warnings "man-db or groff is missing"
fi

begin every_program_and_script_has_help_and_a_man_page
for p in $PROGS; do
	[ -f "$TOP/man/$p.1" ] || bad "no man/$p.1"
done
for s in $SCRIPTS; do
	run "$TOP/scripts/$s" --help
	expect_rc 0; expect_out "Usage: $s"; expect_out "$s(1)"
	[ -f "$TOP/man/$s.1" ] || bad "no man/$s.1"
	grep -q "^\.Nm $s" "$TOP/man/$s.1" || bad "man/$s.1 does not name $s"
done
end

begin install_and_uninstall_put_back_what_was_there
case $BIN in
*/build-san/bin) san=1 ;;
*/build-tsan/bin) san=thread ;;
*) san= ;;
esac
root="$T/root"
if make -s -C "$TOP" install SAN="$san" DESTDIR="$root" PREFIX=/usr/local \
	>"$T/make.out" 2>&1; then
	for p in $PROGS $SCRIPTS; do
		[ -x "$root/usr/local/bin/$p" ] || bad "no bin/$p"
		[ -f "$root/usr/local/share/man/man1/$p.1" ] || bad "no man1/$p.1"
		[ -n "$(find "$root/usr/local/share" -path '*bash-completion/completions/'"$p")" ] ||
			bad "no bash completion for $p"
	done
	[ -f "$root/usr/local/share/man/man5/cloudwx.5" ] || bad "no man5/cloudwx.5"
	# an installed script runs the programs installed beside it
	if have pnmcat; then
		mkdir "$T/sheet"
		(cd "$T/sheet" && env -u CLOUDRENDER PATH=/usr/bin:/bin SHEET_TILE=24x16 \
			"$root/usr/local/bin/genus-sheet" g.png --quality low --noise-size 16) \
			>"$T/sheet.out" 2>&1 || bad "installed genus-sheet failed: $(head -c 300 "$T/sheet.out")"
		[ -s "$T/sheet/g.png" ] || bad "installed genus-sheet wrote nothing"
	fi
	make -s -C "$TOP" uninstall SAN="$san" DESTDIR="$root" PREFIX=/usr/local >"$T/make.out" 2>&1 ||
		bad "make uninstall failed: $(head -c 300 "$T/make.out")"
	left=$(find "$root" -type f)
	[ -z "$left" ] || bad "make uninstall left: $left"
else
	bad "make install failed: $(head -c 300 "$T/make.out")"
fi
end
