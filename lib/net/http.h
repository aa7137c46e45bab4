/* fetch.h - one HTTP GET with libcurl (timeouts, a size cap, the
 * Retry-After header), query-string building, and the text hygiene every
 * message about a response needs: a secret (an API key) redacted, control
 * characters escaped, HTML reduced to its text.  No retries and no provider
 * knowledge here: that is mbfetch.h. */
#ifndef CS_FETCH_H
#define CS_FETCH_H

#include "core/err.h" /* CS_EAUTH, CS_EREQUEST, CS_ERATE, CS_ENET */

#include <stddef.h>

/* What cs_fetch_get replaces a secret with in every text it hands out. */
#define CS_REDACTED "REDACTED"

struct cs_fetch_req {
	const char *url;
	double connect_timeout_s;  /* > 0 */
	double timeout_s;          /* whole transfer, > 0 */
	size_t max_bytes;          /* body cap (after decompression) */
	const char *user_agent;
	const char *secret;        /* redacted from messages; may be NULL */
	int https_only_redirects;  /* follow redirects to https only */
};

enum cs_fetch_fail {
	CS_FETCH_OK,         /* an HTTP response arrived (any status) */
	CS_FETCH_TIMEOUT,    /* connect or total timeout */
	CS_FETCH_CONNECT,    /* DNS, refused, reset, cut short: worth a retry */
	CS_FETCH_TOO_BIG,    /* the body exceeded max_bytes; transfer aborted */
	CS_FETCH_TLS,        /* certificate or TLS failure: not worth a retry */
	CS_FETCH_OTHER,      /* bad URL, unsupported protocol, out of memory */
};

struct cs_fetch_resp {
	enum cs_fetch_fail fail;
	long status;               /* HTTP status, 0 without a response */
	char *body;                /* malloc'ed, NUL-terminated; len bytes */
	size_t len;
	double retry_after_s;      /* Retry-After in seconds, or -1 */
	char content_type[128];
	double seconds;            /* time the transfer took */
	char error[512];           /* why it failed (secret redacted), or "" */
};

/* Performs one GET.  Returns 0 when an HTTP response arrived (whatever its
 * status) and CS_ENET, CS_EDATA (too big) or CS_EINVAL otherwise, with the
 * reason in resp->error and cs_errmsg().  resp is always initialised; free
 * it with cs_fetch_resp_free. */
int cs_fetch_get(const struct cs_fetch_req *req, struct cs_fetch_resp *resp);
void cs_fetch_resp_free(struct cs_fetch_resp *resp);

/* Calls curl_global_init once per process (thread-safe since curl 7.84). */
int cs_fetch_global_init(void);

/* Appends "&name=value" ("?name=value" when buf has no '?' yet) to the URL
 * in buf, percent-encoding value except for RFC 3986 unreserved characters
 * and those in keep (e.g. ","). CS_EINVAL if it does not fit. */
int cs_query_add(char *buf, size_t size, const char *name, const char *value,
		 const char *keep);

/* Replaces, in place, every occurrence of secret (as is and percent-encoded)
 * in the NUL-terminated s with CS_REDACTED, truncating to size. */
void cs_redact(char *s, size_t size, const char *secret);

/* A one-line excerpt of a response body for a message: the secret redacted,
 * HTML tags and entities of an HTML body dropped, whitespace runs collapsed,
 * control and non-ASCII bytes shown as \xHH, cut to about max chars with
 * "...".  out gets at most outsize bytes. */
void cs_fetch_excerpt(const char *body, size_t len, const char *secret,
		      size_t max, char *out, size_t outsize);

/* 1 when a body looks like HTML (a content type of text/html, or a first
 * non-blank character '<' followed by a letter or '!'). */
int cs_fetch_is_html(const char *body, size_t len, const char *content_type);

#endif
