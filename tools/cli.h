/* cli.h - what every cloudscape program shares at its edge: the program
 * name in messages, exit statuses, number parsing for options, and the
 * progress bar.  (The library never prints; this is the printing side.) */
#ifndef CS_CLI_H
#define CS_CLI_H

#include <stdio.h>

struct cs_info;

enum { EXIT_OK = 0, EXIT_DATA = 1, EXIT_USAGE = 2 };

extern const char *cli_prog; /* set by cli_init() */
extern int cli_quiet, cli_verbose;

/* The signal that asked to stop (SIGINT, SIGTERM, SIGHUP), 0 if none: a
 * program hands it to the library as its cancel flag, which is checked
 * between steps (states, rows, frames), so that no temporary output is
 * left and no file is half written. */
#include <signal.h>
extern volatile sig_atomic_t cli_stop_signal;
/* Catches the stop signals once (SA_RESETHAND: a second one acts at once),
 * leaving alone those this process was started ignoring (nohup, a
 * background job of a shell without job control). */
void cli_catch_stop_signals(void);
/* Stopped by a signal: dies of it, so the shell sees 128 + the signal's
 * number (130 for SIGINT) and a script's loop stops too. */
int cli_die_of_stop_signal(void);

void cli_init(const char *prog);

/* "prog: message\n" on stderr. */
void cli_err(const char *fmt, ...) __attribute__((format(printf, 1, 2)));

/* Prints "prog: message" and "Try 'prog --help'." and exits with status 2. */
_Noreturn void cli_usage_error(const char *fmt, ...)
	__attribute__((format(printf, 1, 2)));

/* Parses a whole decimal integer in [lo, hi] for option opt, or exits with
 * a usage error that names the option. */
long cli_long(const char *opt, const char *s, long lo, long hi);
/* The argument of a program's single -o: a usage error the second time
 * (*given counts them). */
const char *cli_one_output(int *given, const char *arg);

/* Parses a whole number in [lo, hi] (finite), or exits with a usage error. */
double cli_double(const char *opt, const char *s, double lo, double hi);
/* The index of s among the NULL-terminated names (any case), or a usage
 * error "OPT: 'S' is not A, B or C". */
int cli_choice(const char *opt, const char *s, const char *const names[]);

/* Parses a comma-separated list of exactly n integers in [lo, hi]; a single
 * value is repeated n times.  Exits with a usage error otherwise. */
void cli_long_list(const char *opt, const char *s, long lo, long hi, int n,
		   int *out);

/* Parses a comma-separated list of exactly n numbers in [lo, hi] (finite),
 * or exits with a usage error. */
void cli_double_list(const char *opt, const char *s, double lo, double hi,
		     int n, double *out);

/* Progress bar on stderr, drawn only when stderr is a terminal and not
 * quiet.  Callback-compatible with cs_progress_fn (user = label). */
int cli_progress(void *label, double fraction);
/* Ends the bar line (if one was drawn). */
void cli_progress_done(void);
/* Ends the bar's line so that a message can follow, keeping its start (the
 * ETA): the next call draws it again on a new line. */
void cli_progress_break(void);

/* The time of an option: ISO 8601 with a zone (core/time.h), or "now" (the
 * clock's); exits with a usage error otherwise. */
double cli_time(const char *opt, const char *s);
/* Seconds on the monotonic clock (differences only). */
double cli_mono_s(void);

/* Finishes an --info text (core/info.h) and writes it to standard output;
 * EXIT_OK, or EXIT_DATA with a message when that fails. */
int cli_info_print(struct cs_info *in);

#endif
