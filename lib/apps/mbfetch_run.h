/* mbfetch.h - the mbfetch program as a library call: fetch a site's hourly
 * forecast from meteoblue's Packages API (basic-1h_clouds-1h) or Open-Meteo,
 * retrying as the provider asks, validate it (provider.h), and write it
 * atomically; an opt-in cache.  The API key never leaves this module except
 * in the request itself: every text it produces has the key redacted. */
#ifndef CS_MBFETCH_H
#define CS_MBFETCH_H

#include "net/http.h"
#include "weather/provider.h"

#include <stddef.h>

/* A named place: WGS84 degrees, metres above sea level. */
struct cs_site {
	const char *name;
	double lat_deg, lon_deg, alt_m;
	const char *description;
};

/* The built-in sites (Bern and the places seen from its hills). */
const struct cs_site *cs_sites(int *count);
/* The site of that name (case-insensitive), or NULL. */
const struct cs_site *cs_site_find(const char *name);

/* "meteoblue" or "open-meteo". */
const char *cs_mbfetch_provider_name(enum cs_provider p);

/* The longest API key accepted. */
#define CS_MBFETCH_KEY_MAX 256

enum { CS_LOG_WARN, CS_LOG_INFO };
/* A line for the user (no program name, no newline; key redacted). */
typedef void (*cs_log_fn)(void *user, int level, const char *msg);

struct cs_mbfetch_opts {
	enum cs_provider provider;
	double lat_deg, lon_deg;
	double asl_m;              /* NaN: the provider's elevation model */
	const char *name;          /* label sent to meteoblue, or NULL */
	int days;                  /* forecast days; -1: the provider's default */
	int history_days;          /* days before today, 0.. */
	const char *base_url;      /* NULL: the provider's https server */
	const char *key_file;      /* NULL: $MBFETCH_APIKEY, then the default file */
	const char *output;        /* path, or "-" for standard output */
	double connect_timeout_s;  /* per attempt */
	double timeout_s;          /* whole transfer, per attempt */
	int retries;               /* attempts after the first */
	double retry_delay_s;      /* first back-off; doubles on each retry */
	double retry_max_wait_s;   /* longest wait; a server asking more: give up */
	size_t max_bytes;          /* response size cap */
	const char *cache_dir;     /* NULL: no cache (the default) */
	double cache_max_age_s;
	int dry_run;               /* build the request into url; no network */
	cs_log_fn log;
	void *log_user;
};

/* What a run produced. */
struct cs_mbfetch_result {
	char url[2048];            /* the request, key redacted */
	int attempts;              /* requests made */
	int from_cache;            /* 1 when the output came from the cache */
	struct cs_problems problems; /* why a response was invalid */
};

/* Defaults: meteoblue, Bern, provider's days, 10 s connect, 60 s total,
 * 3 retries from 1 s, 120 s longest wait, 16 MiB, standard output. */
void cs_mbfetch_defaults(struct cs_mbfetch_opts *o);

/* Checks the options (ranges per provider, the base URL); CS_EINVAL. */
int cs_mbfetch_check_opts(const struct cs_mbfetch_opts *o);

/* Fetches, validates and writes.  Returns 0, CS_EINVAL (bad options),
 * CS_EAUTH (no usable key, or refused), CS_EREQUEST, CS_ERATE, CS_ENET,
 * CS_EDATA (an invalid or oversized response: problems in r->problems) or
 * CS_EIO/CS_ENOMEM; the message (key redacted) in cs_errmsg().  An
 * existing output is replaced only by a valid response. */
int cs_mbfetch_run(const struct cs_mbfetch_opts *o, struct cs_mbfetch_result *r);

/* Validates a provider file ("-": standard input) of at most max_bytes.
 * Returns 0 with a one-line summary ("meteoblue, 25 hours, FROM to TO"),
 * CS_EDATA with the problems in *pr (or in cs_errmsg() when pr->count is
 * 0), or CS_EIO. */
int cs_mbfetch_check(const char *path, size_t max_bytes, struct cs_problems *pr,
		     char *summary, size_t size);

/* Validates a response body: JSON at all (an excerpt of what it is
 * instead), the expected provider (expect < 0: any), then
 * cs_provider_check.  Problems and message have secret redacted. */
int cs_mbfetch_validate(int expect, const char *body, size_t len,
			const char *content_type, const char *secret,
			struct cs_problems *pr);

/* The API key: from key_file if given, else $MBFETCH_APIKEY, else
 * $XDG_CONFIG_HOME/cloudscape/meteoblue.key (~/.config/...).  A key file
 * must be a regular file not accessible by group or others.  source gets
 * where the key came from, for messages.  CS_EAUTH on any failure. */
int cs_mbfetch_key(const char *key_file, char *key, size_t size, char *source,
		   size_t ssize);

/* The request URL; key NULL leaves the apikey parameter out. */
int cs_mbfetch_url(const struct cs_mbfetch_opts *o, const char *key, char *url,
		   size_t size);

/* What to make of one attempt. */
struct cs_verdict {
	int code;        /* 0: a body to validate; else a CS_E* code */
	int retry;       /* worth another attempt */
	double wait_s;   /* the least wait the server asks for, or -1 */
	char msg[1024];  /* why, for the user (secret redacted) */
};

/* Judges a response (or a failed transfer): HTTP status, provider error
 * bodies ({"error_message":...}, {"error":true,"reason":...}, HTML), the
 * provider's meaning of 429 and Retry-After. */
void cs_mbfetch_judge(enum cs_provider p, const struct cs_fetch_resp *r,
		      const char *secret, struct cs_verdict *v);

#endif
