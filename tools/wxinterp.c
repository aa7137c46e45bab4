/* wxinterp - describe the sky at a time from hourly provider forecasts. */
#include "cli.h"

#include "core/err.h"
#include "core/time.h"
#include "apps/wxinterp_run.h"
#include "weather/wxset.h"

#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <time.h>

#ifndef CS_VERSION
#define CS_VERSION "unknown"
#endif

static void usage(void)
{
	printf("Usage: wxinterp [options] FILE... [--at TIME | --from TIME --to TIME]\n"
	       "       wxinterp --template [options]\n"
	       "       wxinterp --summary [--daily] [--json] FILE...\n"
	       "Describe the sky from hourly meteoblue or Open-Meteo files: cloud layers\n"
	       "(genus, coverage, base, top), rain, wind, visibility and fog at any minute,\n"
	       "as cloudwx JSON; a series of times as JSON Lines.  Several FILEs of one\n"
	       "site are merged by time (a later file wins where files overlap).\n"
	       "\n"
	       "  -o, --output FILE      write to FILE, atomically (default '-': standard output)\n"
	       "      --no-clobber       never replace an existing file (default: replace it,\n"
	       "                         whole, once the run has succeeded)\n"
	       "      --at TIME          one state at TIME: ISO 8601 with a zone, or 'now'\n"
	       "      --from TIME        first state of a series (default: the first hour)\n"
	       "      --to TIME          last state of a series (default: the last hour)\n"
	       "      --step DURATION    series interval: N with s, m, h or d (default 1h)\n"
	       "      --far FILE         provider file of a distant site (up to 4)\n"
	       "      --far-name NAME    name of the site of the preceding --far\n"
	       "      --site-name NAME   name of the site (default: the provider's, else the\n"
	       "                         coordinates, e.g. '46.950N 7.440E')\n"
	       "      --alt M            ground height of the site, m (default: the file's)\n"
	       "      --max-gap DURATION missing values are interpolated between valid hours\n"
	       "                         at most this far apart (default 3h)\n"
	       "      --fade DURATION    a change of genus fades over this window, up to 6h\n"
	       "                         (default 1h; 0: at once, the rules of each instant)\n"
	       "      --set PATH=VALUE   edit the state: layer.low.coverage=0.8,\n"
	       "                         precipitation=2.5, wind.speed=3, visibility=5000,\n"
	       "                         layer.high=cirrostratus, ... (repeatable)\n"
	       "      --template         the built-in fair-weather state, no input files\n"
	       "                         (indented; edit it by hand or with --set)\n"
	       "      --pretty           indent the JSON (one state only)\n"
	       "      --summary          instead of states, a table of what the sky does each\n"
	       "                         hour (--step): sun, cloud cover, layers, rain, snow,\n"
	       "                         visibility, fog\n"
	       "      --daily            --summary per UTC day: rain totals, hours, genera\n"
	       "      --json             --summary as JSON Lines (one object per row)\n"
	       "  -q, --quiet            no warnings\n"
	       "  -v, --verbose          say what was read and which rule gave each layer\n"
	       "  -h, --help             this help\n"
	       "      --version          print the version\n"
	       "\n"
	       "Exit status: 0 success, 1 data or runtime error, 2 usage error; stopped\n"
	       "by SIGINT (Ctrl-C), SIGTERM or SIGHUP it removes its temporary output and\n"
	       "dies of the signal (130 for SIGINT in the shell).\n"
	       "See wxinterp(1), cloudwx(5).\n");
}

static void print_note(void *user, int level, const char *msg)
{
	(void)user;
	if ((level == 1 && !cli_quiet) || (level == 2 && cli_verbose))
		cli_err("%s", msg);
}

static double when(const char *opt, const char *s)
{
	return cli_time(opt, s);
}

static double duration(const char *opt, const char *s)
{
	double v;
	if (cs_duration_parse(s, &v) != CS_OK)
		cli_usage_error("%s: %s", opt, cs_errmsg());
	return v;
}

enum {
	OPT_AT = 256, OPT_FROM, OPT_TO, OPT_STEP, OPT_FAR, OPT_FAR_NAME,
	OPT_SITE_NAME, OPT_ALT, OPT_MAX_GAP, OPT_SET, OPT_TEMPLATE, OPT_PRETTY,
	OPT_VERSION, OPT_SUMMARY, OPT_DAILY, OPT_JSON, OPT_NO_CLOBBER, OPT_FADE,
};

int main(int argc, char **argv)
{
	static const struct option longopts[] = {
		{"output", required_argument, NULL, 'o'},
		{"no-clobber", no_argument, NULL, OPT_NO_CLOBBER},
		{"at", required_argument, NULL, OPT_AT},
		{"from", required_argument, NULL, OPT_FROM},
		{"to", required_argument, NULL, OPT_TO},
		{"step", required_argument, NULL, OPT_STEP},
		{"far", required_argument, NULL, OPT_FAR},
		{"far-name", required_argument, NULL, OPT_FAR_NAME},
		{"site-name", required_argument, NULL, OPT_SITE_NAME},
		{"alt", required_argument, NULL, OPT_ALT},
		{"max-gap", required_argument, NULL, OPT_MAX_GAP},
		{"fade", required_argument, NULL, OPT_FADE},
		{"set", required_argument, NULL, OPT_SET},
		{"template", no_argument, NULL, OPT_TEMPLATE},
		{"pretty", no_argument, NULL, OPT_PRETTY},
		{"summary", no_argument, NULL, OPT_SUMMARY},
		{"daily", no_argument, NULL, OPT_DAILY},
		{"json", no_argument, NULL, OPT_JSON},
		{"quiet", no_argument, NULL, 'q'},
		{"verbose", no_argument, NULL, 'v'},
		{"help", no_argument, NULL, 'h'},
		{"version", no_argument, NULL, OPT_VERSION},
		{NULL, 0, NULL, 0},
	};
	struct cs_wxinterp_opts o;
	int opt, have_step = 0, daily = 0, output_given = 0;

	cli_init("wxinterp");
	cs_wxinterp_defaults(&o);
	while ((opt = getopt_long(argc, argv, "o:qvh", longopts, NULL)) != -1) {
		switch (opt) {
		case 'o':
			o.output = cli_one_output(&output_given, optarg);
			break;
		case OPT_NO_CLOBBER: o.no_clobber = 1; break;
		case OPT_AT: o.at_utc = when("--at", optarg); o.have_at = 1; break;
		case OPT_FROM: o.from_utc = when("--from", optarg); o.have_from = 1; break;
		case OPT_TO: o.to_utc = when("--to", optarg); o.have_to = 1; break;
		case OPT_STEP: o.step_s = duration("--step", optarg); have_step = 1; break;
		case OPT_FAR:
			if (o.nfar == CS_WX_MAX_FAR)
				cli_usage_error("--far: at most %d far sites", CS_WX_MAX_FAR);
			o.far[o.nfar++] = optarg;
			break;
		case OPT_FAR_NAME:
			if (o.nfar == 0 || o.far_name[o.nfar - 1] != NULL)
				cli_usage_error("--far-name names the site of the --far "
						"FILE before it");
			if (strlen(optarg) > 63)
				cli_usage_error("--far-name: at most 63 bytes");
			o.far_name[o.nfar - 1] = optarg;
			break;
		case OPT_SITE_NAME:
			if (strlen(optarg) > 63)
				cli_usage_error("--site-name: at most 63 bytes");
			o.site_name = optarg;
			break;
		case OPT_ALT: o.alt_m = cli_double("--alt", optarg, -500, 9000); o.have_alt = 1; break;
		case OPT_MAX_GAP:
			o.max_gap_s = duration("--max-gap", optarg);
			if (o.max_gap_s < 3600)
				cli_usage_error("--max-gap: at least 1h (the step of the data)");
			break;
		case OPT_FADE:
			if (optarg[0] == '-')
				cli_usage_error("--fade: '%s' is not a duration of 0 or more", optarg);
			o.fade_s = strcmp(optarg, "0") == 0 ? 0 : duration("--fade", optarg);
			if (o.fade_s > CS_WX_FADE_MAX_S)
				cli_usage_error("--fade: at most 6h");
			break;
		case OPT_SET:
			if (o.nsets == CS_WXINTERP_MAX_SETS)
				cli_usage_error("--set: at most %d edits", CS_WXINTERP_MAX_SETS);
			if (cs_wx_set_check(optarg) != CS_OK)
				cli_usage_error("--set %s", cs_errmsg());
			o.sets[o.nsets++] = optarg;
			break;
		case OPT_TEMPLATE: o.template_state = 1; break;
		case OPT_PRETTY: o.pretty = 1; break;
		case OPT_SUMMARY: o.summary = o.summary ? o.summary : 1; break;
		case OPT_DAILY: daily = 1; break;
		case OPT_JSON: o.summary_json = 1; break;
		case 'q': cli_quiet = 1; break;
		case 'v': cli_verbose = 1; break;
		case 'h': usage(); return EXIT_OK;
		case OPT_VERSION: printf("wxinterp (cloudscape) %s\n", CS_VERSION); return EXIT_OK;
		default:
			fprintf(stderr, "Try 'wxinterp --help' for more information.\n");
			return EXIT_USAGE;
		}
	}
	for (; optind < argc; optind++) {
		if (o.ninputs == CS_WXINTERP_MAX_INPUTS)
			cli_usage_error("at most %d input files", CS_WXINTERP_MAX_INPUTS);
		o.inputs[o.ninputs++] = argv[optind];
	}
	if (daily && !o.summary)
		cli_usage_error("--daily goes with --summary");
	if (daily)
		o.summary = 2;
	if (o.summary_json && !o.summary)
		cli_usage_error("--json goes with --summary");
	if (daily && have_step)
		cli_usage_error("--daily sums the hours of each day: no --step with it");
	if (o.have_at && have_step)
		cli_usage_error("--step sets the interval of a series; --at gives one time");
	if (o.template_state && o.have_from != o.have_to)
		cli_usage_error("--template: a series needs both --from and --to");
	/* the template is indented for editing, unless it is a series */
	if (o.template_state && !o.have_from)
		o.pretty = 1;

	o.note = print_note;
	o.cancel = &cli_stop_signal;
	cli_catch_stop_signals();
	struct cs_wxinterp_result r;
	int rc = cs_wxinterp_run(&o, &r);
	if (cli_stop_signal) {
		cli_err("%s", rc == CS_OK ? "interrupted after the output was "
			"written" : cs_errmsg());
		return cli_die_of_stop_signal();
	}
	if (rc != CS_OK) {
		cli_err("%s", cs_errmsg());
		if (rc == CS_EINVAL)
			fprintf(stderr, "Try 'wxinterp --help' for more information.\n");
		return rc == CS_EINVAL ? EXIT_USAGE : EXIT_DATA;
	}
	if (cli_verbose)
		cli_err("wrote %ld %s%s to %s", r.nstates, o.summary ? "row" : "state", r.nstates == 1 ? "" : "s",
			strcmp(o.output, "-") == 0 ? "standard output" : o.output);
	return EXIT_OK;
}
