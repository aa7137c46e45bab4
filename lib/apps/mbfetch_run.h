/* mbfetch_run.h - the mbfetch program as a library call: fetch a site's hourly
 * forecast from meteoblue's Packages API (basic-1h_clouds-1h) or Open-Meteo,
 * retrying as the provider asks, validate it (provider.h), and write it
 * atomically; an opt-in cache.  The API key never leaves this module except
 * in the request itself: every text it produces has the key redacted. */
#ifndef CS_MBFETCH_H
#define CS_MBFETCH_H

#include "net/http.h"
#include "net/requests.h"
#include "net/verdict.h"
#include "weather/places.h"
#include "weather/provider.h"

#include <stddef.h>

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
	int no_clobber;            /* never replace an existing file */
	double connect_timeout_s;  /* per attempt */
	double timeout_s;          /* whole transfer, per attempt */
	int retries;               /* attempts after the first */
	double retry_delay_s;      /* first back-off; doubles on each retry */
	double retry_max_wait_s;   /* longest wait; a server asking more: give up */
	size_t max_bytes;          /* response size cap */
	const char *cache_dir;     /* NULL: no cache (the default) */
	double cache_max_age_s;
	int radiation;             /* also ask for the radiation at the hour
				      (meteoblue solar-1h, Open-Meteo *_instant) */
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

/* Whether URL's host is this machine: exactly localhost (any case, with or
 * without the root dot), an IPv4 address in 127.0.0.0/8 or [::1].  Over
 * http to any other host the API key travels unencrypted (a warning). */
int cs_mbfetch_is_loopback(const char *url);

/* The request URL of the options (cs_request_url); key NULL leaves the
 * apikey parameter out. */
int cs_mbfetch_url(const struct cs_mbfetch_opts *o, const char *key, char *url,
		   size_t size);

#endif
