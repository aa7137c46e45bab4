/* mbfetch - fetch an hourly forecast for a site, validate it, write it. */
#include "cli.h"

#include "core/err.h"
#include "apps/mbfetch_run.h"

#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#ifndef CS_VERSION
#define CS_VERSION "unknown"
#endif

/* Exit statuses beyond cli.h's 0, 1 and 2 (see mbfetch(1)). */
enum { EXIT_AUTH = 3, EXIT_REQUEST = 4, EXIT_RATE = 5, EXIT_NET = 6, EXIT_INVALID = 7 };

static void usage(void)
{
	printf("Usage: mbfetch [options] [-o FILE]\n"
	       "       mbfetch --check FILE...\n"
	       "       mbfetch --list-sites\n"
	       "Fetch the hourly forecast of a site (cloud cover by level, precipitation,\n"
	       "wind, visibility...) from meteoblue or Open-Meteo, validate it and write\n"
	       "the provider's JSON, whole or not at all.\n"
	       "\n"
	       "  -o, --output FILE        where to write ('-' = standard output, the default)\n"
	       "      --no-clobber         never replace an existing file (default: replace\n"
	       "                           it, whole, with a valid response only)\n"
	       "      --provider NAME      meteoblue (default; needs an API key) or open-meteo\n"
	       "      --site NAME          a built-in site (default Bern; see --list-sites)\n"
	       "      --lat DEG, --lon DEG any place, WGS84 degrees (instead of --site)\n"
	       "      --asl M              height above sea level (default: the site's; with\n"
	       "                           --lat/--lon the provider's elevation model)\n"
	       "      --days N             forecast days: meteoblue 1..7, open-meteo 0..16\n"
	       "                           (default: the provider's)\n"
	       "      --history-days N     days before today: meteoblue 0..4, open-meteo\n"
	       "                           0..92 (default 0)\n"
	       "      --radiation          also the radiation at each hour (GHI, DNI, DHI):\n"
	       "                           meteoblue's solar-1h package (the key must\n"
	       "                           include it), Open-Meteo's *_instant variables\n"
	       "      --key-file FILE      meteoblue API key file, mode 600 (default:\n"
	       "                           $MBFETCH_APIKEY, then\n"
	       "                           ~/.config/cloudscape/meteoblue.key)\n"
	       "      --base-url URL       another server: a mirror, a test server\n"
	       "      --connect-timeout S  seconds to connect, per attempt (default 10)\n"
	       "      --timeout S          seconds for a whole attempt (default 60)\n"
	       "      --retries N          retries after timeouts, network errors, HTTP 5xx\n"
	       "                           and 429, 0..100 (default 3)\n"
	       "      --retry-delay-ms MS  first back-off, doubled on each retry (default 1000)\n"
	       "      --retry-max-wait S   longest wait; a server asking for longer ends the\n"
	       "                           run (default 120)\n"
	       "      --max-bytes N[k|M]   response size cap (default 16M)\n"
	       "      --cache DIR          reuse a response younger than --cache-max-age\n"
	       "                           (off by default: meteoblue's free terms forbid it)\n"
	       "      --cache-max-age S    (default 3600)\n"
	       "      --dry-run            print the request URL (key redacted) and exit\n"
	       "      --check              validate the FILEs given ('-' = standard input)\n"
	       "                           and print each problem with field and index\n"
	       "      --list-sites         list the built-in sites and exit\n"
	       "  -q, --quiet              no warnings (retries, cache)\n"
	       "  -v, --verbose            report each request and answer\n"
	       "  -h, --help               this help\n"
	       "      --version            print the version\n"
	       "\n"
	       "Environment: MBFETCH_APIKEY (the meteoblue key; never give it as an option).\n"
	       "Exit status: 0 success, 1 other runtime error, 2 usage error,\n"
	       "3 authentication (no key, unsafe key file, key refused), 4 request rejected\n"
	       "(HTTP 400, 404...), 5 rate limit (HTTP 429), 6 network or server error\n"
	       "(timeout, connection, HTTP 5xx), 7 invalid data (also from --check).\n"
	       "See mbfetch(1).\n");
}

static int exit_status(int rc)
{
	switch (rc) {
	case CS_OK: return EXIT_OK;
	case CS_EINVAL: return EXIT_USAGE;
	case CS_EAUTH: return EXIT_AUTH;
	case CS_EREQUEST: return EXIT_REQUEST;
	case CS_ERATE: return EXIT_RATE;
	case CS_ENET: return EXIT_NET;
	case CS_EDATA: return EXIT_INVALID;
	default: return EXIT_DATA;
	}
}

static void list_sites(void)
{
	int n;
	const struct cs_place *s = cs_places(&n);
	for (int i = 0; i < n; i++)
		printf("%-10s %9.5f %9.5f %5.0f m  %s\n", s[i].name, s[i].lat_deg,
		       s[i].lon_deg, s[i].alt_m, s[i].description);
}

static void print_problems(const char *prefix, const struct cs_problems *pr)
{
	int kept = pr->count < 32 ? pr->count : 32;
	for (int i = 0; i < kept; i++)
		cli_err("%s%s", prefix, pr->msg[i]);
	if (pr->count > kept)
		cli_err("%s... and %d more problems", prefix, pr->count - kept);
}

static int check_files(int argc, char **argv, size_t max_bytes)
{
	int status = EXIT_OK;
	for (int i = 0; i < argc; i++) {
		struct cs_problems pr;
		char summary[256], prefix[4200];
		int rc = cs_mbfetch_check(argv[i], max_bytes, &pr, summary, sizeof summary);
		snprintf(prefix, sizeof prefix, "%s: ", argv[i]);
		if (rc == CS_OK) {
			if (!cli_quiet)
				printf("%s: ok: %s\n", argv[i], summary);
			continue;
		}
		if (pr.count > 0) {
			print_problems(prefix, &pr);
			cli_err("%s: invalid: %d problem%s", argv[i], pr.count,
				pr.count == 1 ? "" : "s");
		} else if (rc == CS_EDATA) {
			cli_err("%s: %s", argv[i], cs_errmsg());
		} else {
			cli_err("%s", cs_errmsg());
		}
		if (status == EXIT_OK)
			status = rc == CS_EDATA ? EXIT_INVALID : EXIT_DATA;
	}
	return status;
}

static void log_line(void *user, int level, const char *msg)
{
	(void)user;
	if (level == CS_LOG_WARN ? !cli_quiet : cli_verbose)
		cli_err("%s", msg);
}

static size_t parse_bytes(const char *s)
{
	char buf[64];
	size_t n = strlen(s);
	if (n == 0 || n >= sizeof buf)
		cli_usage_error("--max-bytes: '%s' is not a size", s);
	strcpy(buf, s);
	double mult = 1.0;
	switch (buf[n - 1]) {
	case 'k': case 'K': mult = 1024.0; buf[n - 1] = '\0'; break;
	case 'M': mult = 1024.0 * 1024.0; buf[n - 1] = '\0'; break;
	case 'G': mult = 1024.0 * 1024.0 * 1024.0; buf[n - 1] = '\0'; break;
	default: break;
	}
	long v = cli_long("--max-bytes", buf, 1, 1L << 30);
	if ((double)v * mult > (double)(1L << 30))
		cli_usage_error("--max-bytes: %s is more than 1G", s);
	return (size_t)((double)v * mult);
}

enum {
	OPT_PROVIDER = 256, OPT_SITE, OPT_LAT, OPT_LON, OPT_ASL, OPT_DAYS, OPT_HISTORY,
	OPT_KEY_FILE, OPT_BASE_URL, OPT_CONNECT_TIMEOUT, OPT_TIMEOUT, OPT_RETRIES,
	OPT_RETRY_DELAY, OPT_RETRY_MAX_WAIT, OPT_MAX_BYTES, OPT_CACHE, OPT_CACHE_AGE,
	OPT_DRY_RUN, OPT_CHECK, OPT_LIST_SITES, OPT_NO_CLOBBER, OPT_VERSION, OPT_RADIATION,
};

int main(int argc, char **argv)
{
	static const struct option longopts[] = {
		{"output", required_argument, NULL, 'o'},
		{"no-clobber", no_argument, NULL, OPT_NO_CLOBBER},
		{"provider", required_argument, NULL, OPT_PROVIDER},
		{"site", required_argument, NULL, OPT_SITE},
		{"lat", required_argument, NULL, OPT_LAT},
		{"lon", required_argument, NULL, OPT_LON},
		{"asl", required_argument, NULL, OPT_ASL},
		{"days", required_argument, NULL, OPT_DAYS},
		{"history-days", required_argument, NULL, OPT_HISTORY},
		{"key-file", required_argument, NULL, OPT_KEY_FILE},
		{"base-url", required_argument, NULL, OPT_BASE_URL},
		{"connect-timeout", required_argument, NULL, OPT_CONNECT_TIMEOUT},
		{"timeout", required_argument, NULL, OPT_TIMEOUT},
		{"retries", required_argument, NULL, OPT_RETRIES},
		{"retry-delay-ms", required_argument, NULL, OPT_RETRY_DELAY},
		{"retry-max-wait", required_argument, NULL, OPT_RETRY_MAX_WAIT},
		{"max-bytes", required_argument, NULL, OPT_MAX_BYTES},
		{"cache", required_argument, NULL, OPT_CACHE},
		{"cache-max-age", required_argument, NULL, OPT_CACHE_AGE},
		{"dry-run", no_argument, NULL, OPT_DRY_RUN},
		{"radiation", no_argument, NULL, OPT_RADIATION},
		{"check", no_argument, NULL, OPT_CHECK},
		{"list-sites", no_argument, NULL, OPT_LIST_SITES},
		{"quiet", no_argument, NULL, 'q'},
		{"verbose", no_argument, NULL, 'v'},
		{"help", no_argument, NULL, 'h'},
		{"version", no_argument, NULL, OPT_VERSION},
		{NULL, 0, NULL, 0},
	};
	struct cs_mbfetch_opts o;
	const char *site = NULL;
	double lat = NAN, lon = NAN, asl = NAN;
	int check = 0, fetch_opts = 0, opt, output_given = 0;

	cli_init("mbfetch");
	cs_mbfetch_defaults(&o);
	while ((opt = getopt_long(argc, argv, "o:qvh", longopts, NULL)) != -1) {
		fetch_opts += opt != 'q' && opt != 'v' && opt != OPT_CHECK &&
			      opt != OPT_MAX_BYTES;
		switch (opt) {
		case 'o':
			o.output = cli_one_output(&output_given, optarg);
			break;
		case OPT_NO_CLOBBER: o.no_clobber = 1; break;
		case OPT_PROVIDER:
			if (strcasecmp(optarg, "meteoblue") == 0)
				o.provider = CS_PROVIDER_METEOBLUE;
			else if (strcasecmp(optarg, "open-meteo") == 0 ||
				 strcasecmp(optarg, "openmeteo") == 0)
				o.provider = CS_PROVIDER_OPENMETEO;
			else
				cli_usage_error("--provider: '%s' is not meteoblue or open-meteo",
						optarg);
			break;
		case OPT_SITE:
			if (cs_place_find(optarg) == NULL)
				cli_usage_error("--site: unknown site '%s' (see --list-sites)",
						optarg);
			site = optarg;
			break;
		case OPT_LAT: lat = cli_double("--lat", optarg, -90.0, 90.0); break;
		case OPT_LON: lon = cli_double("--lon", optarg, -180.0, 180.0); break;
		case OPT_ASL: asl = cli_double("--asl", optarg, -500.0, 9000.0); break;
		case OPT_DAYS: o.days = (int)cli_long("--days", optarg, 0, 16); break;
		case OPT_HISTORY:
			o.history_days = (int)cli_long("--history-days", optarg, 0, 92);
			break;
		case OPT_KEY_FILE: o.key_file = optarg; break;
		case OPT_BASE_URL: o.base_url = optarg; break;
		case OPT_CONNECT_TIMEOUT:
			o.connect_timeout_s = cli_double("--connect-timeout", optarg, 0.001, 3600.0);
			break;
		case OPT_TIMEOUT: o.timeout_s = cli_double("--timeout", optarg, 0.001, 86400.0); break;
		case OPT_RETRIES: o.retries = (int)cli_long("--retries", optarg, 0, 100); break;
		case OPT_RETRY_DELAY:
			o.retry_delay_s = (double)cli_long("--retry-delay-ms", optarg, 0,
							    3600000L) / 1000.0;
			break;
		case OPT_RETRY_MAX_WAIT:
			o.retry_max_wait_s = cli_double("--retry-max-wait", optarg, 0.0, 86400.0);
			break;
		case OPT_MAX_BYTES: o.max_bytes = parse_bytes(optarg); break;
		case OPT_CACHE: o.cache_dir = optarg; break;
		case OPT_CACHE_AGE:
			o.cache_max_age_s = cli_double("--cache-max-age", optarg, 0.0, 1e9);
			break;
		case OPT_DRY_RUN: o.dry_run = 1; break;
		case OPT_RADIATION: o.radiation = 1; break;
		case OPT_CHECK: check = 1; break;
		case OPT_LIST_SITES: list_sites(); return EXIT_OK;
		case 'q': cli_quiet = 1; break;
		case 'v': cli_verbose = 1; break;
		case 'h': usage(); return EXIT_OK;
		case OPT_VERSION: printf("mbfetch (cloudscape) %s\n", CS_VERSION); return EXIT_OK;
		default:
			fprintf(stderr, "Try 'mbfetch --help' for more information.\n");
			return EXIT_USAGE;
		}
	}
	if (check) {
		if (fetch_opts)
			cli_usage_error("--check validates files; it takes no fetching options");
		if (optind == argc)
			cli_usage_error("--check: no FILE given");
		return check_files(argc - optind, argv + optind, o.max_bytes);
	}
	if (optind < argc) {
		/* never echo what may be a key pasted on the command line */
		const char *a = argv[optind];
		size_t n = strlen(a);
		if (n >= 12 && strspn(a, "0123456789abcdefghijklmnopqrstuvwxyz"
				      "ABCDEFGHIJKLMNOPQRSTUVWXYZ-_") == n)
			cli_usage_error("unexpected argument (it looks like an API key: "
					"never give it as an argument; see --key-file "
					"and MBFETCH_APIKEY)");
		cli_usage_error("unexpected argument '%s'", a);
	}
	if (site && (!isnan(lat) || !isnan(lon)))
		cli_usage_error("--site and --lat/--lon name two places; give one");
	if (isnan(lat) != isnan(lon))
		cli_usage_error("--lat and --lon go together");
	if (site) {
		const struct cs_place *s = cs_place_find(site);
		o.lat_deg = s->lat_deg;
		o.lon_deg = s->lon_deg;
		o.asl_m = s->alt_m;
		o.name = s->name;
	} else if (!isnan(lat)) {
		o.lat_deg = lat;
		o.lon_deg = lon;
		o.asl_m = NAN;
		o.name = NULL;
	}
	if (!isnan(asl))
		o.asl_m = asl;
	o.log = log_line;
	struct cs_mbfetch_result r;
	int rc = cs_mbfetch_run(&o, &r);
	if (rc == CS_EINVAL)
		cli_usage_error("%s", cs_errmsg());
	if (rc != CS_OK) {
		cli_err("%s", cs_errmsg());
		print_problems("", &r.problems);
		return exit_status(rc);
	}
	if (o.dry_run)
		printf("%s\n", r.url);
	return EXIT_OK;
}
