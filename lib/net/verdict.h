/* verdict.h - what a provider's answer means: an HTTP status and error
 * body judged (retry or not, how long to wait), and a body validated as
 * the provider's JSON.  The request side is requests.h. */
#ifndef CS_VERDICT_H
#define CS_VERDICT_H

#include "net/http.h"
#include "net/requests.h"
#include "weather/provider.h"

#include <stddef.h>

/* cs_error with the secret (may be NULL) redacted from the message;
 * returns code. */
int cs_error_redacted(int code, const char *secret, const char *fmt, ...)
	__attribute__((format(printf, 3, 4)));

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

#endif
