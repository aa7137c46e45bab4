# bash completion for the cloudscape programs: cloudrender, mbfetch,
# noisebake, terrainprep, wxinterp (and the scripts genus-sheet,
# quality-study, radiation-study, weather-sheet, timelapse,
# slurm-timelapse).
#
# The options are read from the program's own --help when first completed,
# so they always match the program that is installed; the values of the
# options that take one of a few words (--quality, --format, ...) are listed
# below, files otherwise.  Installed once per program name (bash-completion
# loads completions/NAME on demand); sourcing it registers all of them.

# _cloudscape_parse PROG: the options in PROG --help, all and those taking
# a value ("-o, --output FILE"), cached per program.
_cloudscape_parse()
{
	local key=${1//[^A-Za-z0-9]/_} help
	eval "[[ -n \${_cloudscape_opts_$key+x} ]]" && return 0
	help=$(LC_ALL=C "$1" --help 2>/dev/null) || return 1
	local opts args
	opts=$(printf '%s\n' "$help" | grep -oE '(^|[ ,(])--?[A-Za-z][A-Za-z0-9-]*' |
		sed 's/^[ ,(]//' | sort -u | tr '\n' ' ')
	args=$(printf '%s\n' "$help" | awk '{
		# single spaces: "--size WxH" takes a value, "--float    EXR: ..."
		# (a description after a gap) does not
		n = split($0, w, / /); pending = ""
		for (i = 1; i <= n; i++) {
			if (w[i] !~ /^--?[A-Za-z][A-Za-z0-9-]*,?$/) { pending = ""; continue }
			o = w[i]; sub(/,$/, "", o)
			if (w[i] ~ /,$/) { pending = pending " " o; continue }
			if (w[i + 1] ~ /^[A-Z]/) printf "%s%s ", o, pending
			pending = ""
		}
	}')
	eval "_cloudscape_opts_$key=\$opts; _cloudscape_args_$key=\$args"
}

# _cloudscape_values PROG OPTION: the words OPTION takes, or nothing (files).
_cloudscape_values()
{
	case ${1##*/}:$2 in
	cloudrender:--quality) echo low medium high reference ;;
	cloudrender:--projection) echo perspective fisheye equirect ;;
	cloudrender:--view) "$1" --list-views 2>/dev/null | awk '{ print $1 }' ;;
	cloudrender:-of | cloudrender:--of | cloudrender:--output-format) echo PNG EXR GTiff JPEG png exr gtiff jpeg ;;
	cloudrender:--exposure) echo auto ;;
	cloudrender:--cloud-depth) echo forecast genus ;;
	cloudrender:--sky-level) echo preetham ineichen ;;
	cloudrender:--march) echo standard naive skip adaptive ;;
	cloudrender:--light-march) echo auto cache geometric uniform quadratic cone ;;
	cloudrender:--integrator) echo march reference ;;
	cloudrender:--heap-towers) echo on off ;;
	cloudrender:--deck-lattice) echo diffusion exchange off on ;;
	cloudrender:--ground-sky) echo field dome columns ;;
	cloudrender:--device) echo cpu cuda ;;
	terrainprep:-f | terrainprep:--format) echo exr r16 tif ;;
	terrainprep:-r | terrainprep:--resampling)
		echo near bilinear cubic cubicspline lanczos average rms mode max min med q1 q3 sum ;;
	terrainprep:--fill) echo nearest value none ;;
	terrainprep:--src-nodata) echo none ;;
	terrainprep:--size) echo unity ;;
	mbfetch:--provider) echo meteoblue open-meteo ;;
	mbfetch:--site) "$1" --list-sites 2>/dev/null | awk '{ print tolower($1) }' ;;
	wxinterp:--at | wxinterp:--from | wxinterp:--to) echo now ;;
	cloudrender:--time) echo now ;;
	esac
}

_cloudscape()
{
	local prog=$1 cur=${COMP_WORDS[COMP_CWORD]} prev=
	((COMP_CWORD > 0)) && prev=${COMP_WORDS[COMP_CWORD - 1]}
	COMPREPLY=()
	_cloudscape_parse "$prog" || return 0
	local key=${prog//[^A-Za-z0-9]/_} opts args
	eval "opts=\$_cloudscape_opts_$key; args=\$_cloudscape_args_$key"
	case ${prog##*/} in
	genus-sheet | quality-study | radiation-study | weather-sheet | timelapse | slurm-timelapse)
		# the scripts pass their other options to cloudrender
		local cr=cloudrender dir
		dir=$(dirname -- "$(type -P "$prog")" 2>/dev/null)
		[[ -x $dir/cloudrender ]] && cr=$dir/cloudrender
		if _cloudscape_parse "$cr"; then
			local k2=${cr//[^A-Za-z0-9]/_}
			eval "opts+=\" \$_cloudscape_opts_$k2\"; args+=\" \$_cloudscape_args_$k2\""
		fi
		opts=$(printf '%s\n' $opts | sort -u)
		prog=$cr
		;;
	esac
	if [[ $cur == --*=* ]]; then # --opt=value
		prev=${cur%%=*}
		cur=${cur#*=}
	elif [[ $cur == -* ]]; then
		COMPREPLY=($(compgen -W "$opts" -- "$cur"))
		return 0
	fi
	if [[ " $args " == *" $prev "* ]]; then
		local values
		values=$(_cloudscape_values "$prog" "$prev")
		if [[ -n $values ]]; then
			COMPREPLY=($(compgen -W "$values" -- "$cur"))
			return 0
		fi
	fi
	compopt -o filenames 2>/dev/null
	COMPREPLY=($(compgen -f -- "$cur"))
}

complete -F _cloudscape cloudrender mbfetch noisebake terrainprep wxinterp \
	genus-sheet quality-study radiation-study weather-sheet timelapse slurm-timelapse
