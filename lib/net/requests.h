/* requests.h - the request side of a provider fetch: the API key's sources, a request's checks and its URL.  The answer side
 * is verdict.h; retrying and writing are the program's (apps/mbfetch_run.h). */
#ifndef CS_REQUESTS_H
#define CS_REQUESTS_H

#include "weather/provider.h"

#include <stddef.h>

/* "meteoblue" or "open-meteo". */
const char *cs_mbfetch_provider_name(enum cs_provider p);

/* The longest API key accepted. */
#define CS_MBFETCH_KEY_MAX 256

/* What to ask a provider for. */
struct cs_request {
	enum cs_provider provider;
	double lat_deg, lon_deg;
	double asl_m;              /* NaN: the provider's elevation model */
	const char *name;          /* label sent to meteoblue, or NULL */
	int days;                  /* forecast days; -1: the provider's default */
	int history_days;          /* days before today, 0.. */
	const char *base_url;      /* NULL: the provider's https server */
	int radiation;             /* also the radiation at the hour: meteoblue's
				      solar-1h package, Open-Meteo's
				      *_instant irradiances */
};

/* Checks a request: position, days and history per provider, the base
 * URL.  CS_EINVAL. */
int cs_request_check(const struct cs_request *r);

/* The request URL; key NULL leaves the apikey parameter out.  CS_EINVAL
 * when it does not fit. */
int cs_request_url(const struct cs_request *r, const char *key, char *url,
		   size_t size);

/* The API key: from key_file if given, else $MBFETCH_APIKEY, else
 * $XDG_CONFIG_HOME/cloudscape/meteoblue.key (~/.config/...).  A key file
 * must be a regular file not accessible by group or others.  source gets
 * where the key came from, for messages.  CS_EAUTH on any failure. */
int cs_mbfetch_key(const char *key_file, char *key, size_t size, char *source,
		   size_t ssize);

#endif
