#include "cli.h"

#include "core/err.h"
#include "core/info.h"
#include "core/time.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <time.h>
#include <unistd.h>

const char *cli_prog = "cloudscape";
int cli_quiet, cli_verbose;
volatile sig_atomic_t cli_stop_signal;

static void on_stop_signal(int sig)
{
	cli_stop_signal = sig;
}

void cli_catch_stop_signals(void)
{
	static const int sigs[] = {SIGINT, SIGTERM, SIGHUP};
	for (size_t i = 0; i < sizeof sigs / sizeof sigs[0]; i++) {
		struct sigaction sa, old;
		if (sigaction(sigs[i], NULL, &old) != 0 || old.sa_handler == SIG_IGN)
			continue;
		memset(&sa, 0, sizeof sa);
		sa.sa_handler = on_stop_signal;
		sigemptyset(&sa.sa_mask);
		/* no SA_RESTART: a read of a terminal stops at the signal */
		sa.sa_flags = SA_RESETHAND;
		sigaction(sigs[i], &sa, NULL);
	}
}

int cli_die_of_stop_signal(void)
{
	int sig = cli_stop_signal;
	signal(sig, SIG_DFL);
	raise(sig);
	return 128 + sig;
}

static int bar_drawn;
static int bar_last_pct = -1;

void cli_init(const char *prog)
{
	cli_prog = prog;
}

__attribute__((format(printf, 1, 0)))
static void vmessage(const char *fmt, va_list ap)
{
	fprintf(stderr, "%s: ", cli_prog);
	vfprintf(stderr, fmt, ap);
	fputc('\n', stderr);
}

void cli_err(const char *fmt, ...)
{
	va_list ap;
	va_start(ap, fmt);
	vmessage(fmt, ap);
	va_end(ap);
}

void cli_usage_error(const char *fmt, ...)
{
	va_list ap;
	va_start(ap, fmt);
	vmessage(fmt, ap);
	va_end(ap);
	fprintf(stderr, "Try '%s --help' for more information.\n", cli_prog);
	exit(EXIT_USAGE);
}

long cli_long(const char *opt, const char *s, long lo, long hi)
{
	char *end;
	errno = 0;
	long v = strtol(s, &end, 10);
	if (s[0] == '\0' || *end != '\0' || errno == ERANGE)
		cli_usage_error("%s: '%s' is not an integer", opt, s);
	if (v < lo || v > hi)
		cli_usage_error("%s: %ld is out of range %ld..%ld", opt, v, lo, hi);
	return v;
}

int cli_choice(const char *opt, const char *s, const char *const names[])
{
	char list[512] = "";
	size_t k = 0;
	int n = 0;
	for (; names[n]; n++)
		if (strcasecmp(s, names[n]) == 0)
			return n;
	for (int i = 0; i < n && k < sizeof list; i++)
		k += (size_t)snprintf(list + k, sizeof list - k, "%s%s",
				      i == 0 ? "" : i == n - 1 ? " or " : ", ", names[i]);
	cli_usage_error("%s: '%s' is not %s", opt, s, list);
}

double cli_double(const char *opt, const char *s, double lo, double hi)
{
	char *end;
	errno = 0;
	double v = strtod(s, &end);
	if (s[0] == '\0' || *end != '\0' || errno == ERANGE || !isfinite(v))
		cli_usage_error("%s: '%s' is not a number", opt, s);
	if (v < lo || v > hi)
		cli_usage_error("%s: %g is out of range %g..%g", opt, v, lo, hi);
	return v;
}

/* Splits a comma-separated option value into at most max tokens held in
 * buf; exits with a usage error if there are more or it is too long. */
static int split_list(const char *opt, const char *s, char buf[256], char **tok,
		      int max)
{
	if (strlen(s) >= 256)
		cli_usage_error("%s: list too long", opt);
	strcpy(buf, s);
	int count = 0;
	char *save = NULL;
	for (char *t = strtok_r(buf, ",", &save); t; t = strtok_r(NULL, ",", &save)) {
		if (count == max)
			cli_usage_error("%s: expected %d comma-separated values, got more", opt, max);
		tok[count++] = t;
	}
	return count;
}

void cli_long_list(const char *opt, const char *s, long lo, long hi, int n,
		   int *out)
{
	char buf[256], *tok[64];
	int count = split_list(opt, s, buf, tok, n < 64 ? n : 64);
	for (int i = 0; i < count; i++)
		out[i] = (int)cli_long(opt, tok[i], lo, hi);
	if (count == 1)
		for (int i = 1; i < n; i++)
			out[i] = out[0];
	else if (count != n)
		cli_usage_error("%s: expected 1 or %d comma-separated values, got %d",
				opt, n, count);
}

void cli_double_list(const char *opt, const char *s, double lo, double hi,
		     int n, double *out)
{
	char buf[256], *tok[64];
	int count = split_list(opt, s, buf, tok, n < 64 ? n : 64);
	if (count != n)
		cli_usage_error("%s: expected %d comma-separated numbers", opt, n);
	for (int i = 0; i < count; i++)
		out[i] = cli_double(opt, tok[i], lo, hi);
}

static double bar_start_s = -1.0;

double cli_mono_s(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

/* "1:05" or "1:02:05" */
static void clock_text(char *buf, size_t size, double s)
{
	long t = (long)(s + 0.5);
	if (t >= 3600)
		snprintf(buf, size, "%ld:%02ld:%02ld", t / 3600, t / 60 % 60, t % 60);
	else
		snprintf(buf, size, "%ld:%02ld", t / 60, t % 60);
}

static char bar_label[128]; /* the label last drawn */

int cli_progress(void *label, double fraction)
{
	if (cli_quiet || !isatty(STDERR_FILENO))
		return 0;
	double now = cli_mono_s();
	if (bar_start_s < 0.0)
		bar_start_s = now;
	int pct = (int)(fraction * 100.0 + 0.5);
	const char *text = label ? (const char *)label : "";
	if (pct == bar_last_pct && strncmp(text, bar_label, sizeof bar_label - 1) == 0)
		return 0;
	bar_last_pct = pct;
	snprintf(bar_label, sizeof bar_label, "%s", text);
	enum { W = 40 };
	char bar[W + 1], elapsed[32], eta[32] = "--:--";
	int fill = (int)(fraction * W + 0.5);
	for (int i = 0; i < W; i++)
		bar[i] = i < fill ? '#' : '.';
	bar[W] = '\0';
	double spent = now - bar_start_s;
	clock_text(elapsed, sizeof elapsed, spent);
	/* the rest at the rate so far (after 1 %, when there is a rate) */
	if (fraction >= 0.01 && fraction < 1.0)
		clock_text(eta, sizeof eta, spent * (1.0 - fraction) / fraction);
	else if (fraction >= 1.0)
		snprintf(eta, sizeof eta, "0:00");
	fprintf(stderr, "\r%s: %s [%s] %3d%% %s ETA %s ", cli_prog,
		label ? (const char *)label : "", bar, pct, elapsed, eta);
	fflush(stderr);
	bar_drawn = 1;
	return 0;
}

void cli_progress_break(void)
{
	if (bar_drawn)
		fputc('\n', stderr);
	bar_drawn = 0;
	bar_last_pct = -1;
}

double cli_time(const char *opt, const char *s)
{
	double t;
	if (strcasecmp(s, "now") == 0)
		return (double)time(NULL);
	if (cs_time_parse(s, &t) != CS_OK)
		cli_usage_error("%s: %s", opt, cs_errmsg());
	return t;
}

void cli_progress_done(void)
{
	if (bar_drawn)
		fputc('\n', stderr);
	bar_drawn = 0;
	bar_last_pct = -1;
	bar_start_s = -1.0;
}

int cli_info_print(struct cs_info *in)
{
	char *text = NULL;
	if (cs_info_finish(in, &text) != CS_OK) {
		cli_err("%s", cs_errmsg());
		return EXIT_DATA;
	}
	fputs(text, stdout);
	free(text);
	if (fflush(stdout) != 0 || ferror(stdout)) {
		cli_err("standard output: %s", strerror(errno));
		return EXIT_DATA;
	}
	return EXIT_OK;
}

const char *cli_one_output(int *given, const char *arg)
{
	if ((*given)++)
		cli_usage_error("-o: one output only (given twice)");
	return arg;
}
