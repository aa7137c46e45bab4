/* The answering side of a provider request (see verdict.h): what a
 * response means, whether a body is valid provider JSON. */
#include "net/verdict.h"

#include "core/err.h"
#include "core/fileio.h"
#include "core/json.h"
#include "core/time.h"

#include <cjson/cJSON.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

int cs_error_redacted(int code, const char *secret, const char *fmt, ...)
{
	char buf[1024];
	va_list ap;
	va_start(ap, fmt);
	vsnprintf(buf, sizeof buf, fmt, ap);
	va_end(ap);
	cs_redact(buf, sizeof buf, secret);
	return cs_error(code, "%s", buf);
}

/* ---- judging an answer ---- */

static int ci_contains(const char *s, const char *sub)
{
	size_t n = strlen(sub);
	for (; *s; s++)
		if (strncasecmp(s, sub, n) == 0)
			return 1;
	return 0;
}

/* The provider's own error text in a JSON body, as a sanitised excerpt. */
static int provider_error_text(const char *body, size_t len, const char *secret,
			       char *out, size_t size)
{
	cJSON *j = cJSON_ParseWithLength(body, len);
	if (!cJSON_IsObject(j)) {
		cJSON_Delete(j);
		return 0;
	}
	const cJSON *m = cJSON_GetObjectItemCaseSensitive(j, "error_message");
	const cJSON *e = cJSON_GetObjectItemCaseSensitive(j, "error");
	const cJSON *r = cJSON_GetObjectItemCaseSensitive(j, "reason");
	const char *text = cJSON_IsString(m) ? m->valuestring
			 : cJSON_IsTrue(e) && cJSON_IsString(r) ? r->valuestring
			 : cJSON_IsString(e) ? e->valuestring
			 : cJSON_IsTrue(e) ? "(no reason given)" : NULL;
	if (text)
		cs_fetch_excerpt(text, strlen(text), secret, 400, out, size);
	cJSON_Delete(j);
	return text != NULL;
}

static const char *status_text(long s)
{
	switch (s) {
	case 400: return " Bad Request";
	case 401: return " Unauthorized";
	case 403: return " Forbidden";
	case 404: return " Not Found";
	case 408: return " Request Timeout";
	case 429: return " Too Many Requests";
	case 500: return " Internal Server Error";
	case 502: return " Bad Gateway";
	case 503: return " Service Unavailable";
	case 504: return " Gateway Timeout";
	default: return "";
	}
}

static void judge_transfer(const struct cs_fetch_resp *r, struct cs_verdict *v)
{
	switch (r->fail) {
	case CS_FETCH_TIMEOUT:
	case CS_FETCH_CONNECT:
		v->code = CS_ENET;
		v->retry = 1;
		snprintf(v->msg, sizeof v->msg, "network error: %s", r->error);
		break;
	case CS_FETCH_TOO_BIG:
		v->code = CS_EDATA;
		snprintf(v->msg, sizeof v->msg, "%s", r->error);
		break;
	case CS_FETCH_TLS:
		v->code = CS_ENET;
		snprintf(v->msg, sizeof v->msg, "TLS error: %s", r->error);
		break;
	default:
		v->code = CS_ENET;
		snprintf(v->msg, sizeof v->msg, "cannot fetch: %s", r->error);
		break;
	}
}

void cs_mbfetch_judge(enum cs_provider p, const struct cs_fetch_resp *r,
		      const char *secret, struct cs_verdict *v)
{
	memset(v, 0, sizeof *v);
	v->wait_s = -1.0;
	if (r->fail != CS_FETCH_OK) {
		judge_transfer(r, v);
		cs_redact(v->msg, sizeof v->msg, secret);
		return;
	}
	char text[600];
	int perr = provider_error_text(r->body, r->len, secret, text, sizeof text);
	if (!perr && r->len == 0)
		snprintf(text, sizeof text, "(empty body)");
	else if (!perr)
		cs_fetch_excerpt(r->body, r->len, secret, 300, text, sizeof text);
	long s = r->status;
	const char *what, *note = "";
	if (s >= 200 && s < 300) {
		if (!perr)
			return; /* a body to validate */
		v->code = ci_contains(text, "api key") || ci_contains(text, "apikey") ||
			  ci_contains(text, "authori") ? CS_EAUTH
			: ci_contains(text, "limit") ? CS_ERATE : CS_EREQUEST;
	} else if (s == 401 || s == 403) {
		v->code = CS_EAUTH;
	} else if (s == 429) {
		v->code = CS_ERATE;
		v->retry = 1;
		if (ci_contains(text, "daily")) {
			v->retry = 0;
			note = " (not retried: the daily limit resets at 00:00 UTC)";
		} else if (ci_contains(text, "hourly")) {
			v->retry = 0;
			note = " (not retried: the hourly limit resets at the full hour)";
		} else if (p == CS_PROVIDER_OPENMETEO && ci_contains(text, "minutely")) {
			v->wait_s = 60.0; /* Open-Meteo's counters reset each minute */
		}
	} else if (s == 408 || s >= 500) {
		v->code = CS_ENET;
		v->retry = 1;
	} else if (s >= 400) {
		v->code = ci_contains(text, "api key") || ci_contains(text, "apikey")
			? CS_EAUTH : CS_EREQUEST;
	} else {
		v->code = CS_EREQUEST;
		note = " (unexpected status)";
	}
	/* a Retry-After the server sends wins over our guesses */
	if (r->retry_after_s >= 0.0 && (s == 429 || s == 503)) {
		v->retry = 1;
		v->wait_s = r->retry_after_s;
	}
	switch (v->code) {
	case CS_EAUTH: what = "authentication failed"; break;
	case CS_ERATE: what = "rate limit exceeded"; break;
	case CS_ENET: what = s == 408 ? "server timeout" : "server error"; break;
	default: what = "request rejected"; break;
	}
	snprintf(v->msg, sizeof v->msg, "%s (%s, HTTP %ld%s): %s%s", what,
		 cs_mbfetch_provider_name(p), s, status_text(s), text, note);
	cs_redact(v->msg, sizeof v->msg, secret);
}

/* ---- validation ---- */

/* What a body that is not text looks like, from its magic bytes: "a PNG
 * image", ..., "binary data"; NULL for text (no NUL and hardly any control
 * characters in its first 512 bytes), whose excerpt can be shown. */
static const char *binary_kind(const char *body, size_t len)
{
	static const struct {
		const char *magic;
		size_t n;
		const char *what;
	} kinds[] = {
		{"\x89PNG\r\n\x1a\n", 8, "a PNG image"},
		{"\xff\xd8\xff", 3, "a JPEG image"},
		{"GIF8", 4, "a GIF image"},
		{"\x76\x2f\x31\x01", 4, "an OpenEXR image"},
		{"II*\0", 4, "a TIFF image"},
		{"MM\0*", 4, "a TIFF image"},
		{"\x1f\x8b", 2, "gzip-compressed data (not decompressed)"},
		{"PK\x03\x04", 4, "a zip archive"},
		{"%PDF", 4, "a PDF document"},
		{"\x7f" "ELF", 4, "a program (ELF)"},
	};
	for (size_t i = 0; i < sizeof kinds / sizeof kinds[0]; i++)
		if (len >= kinds[i].n && memcmp(body, kinds[i].magic, kinds[i].n) == 0)
			return kinds[i].what;
	size_t n = len < 512 ? len : 512, ctl = 0;
	for (size_t i = 0; i < n; i++) {
		unsigned char c = (unsigned char)body[i];
		if (c == 0)
			return "binary data";
		ctl += c < 0x20 && c != '\t' && c != '\n' && c != '\r';
	}
	return ctl * 20 > n ? "binary data" : NULL;
}

int cs_mbfetch_validate(int expect, const char *body, size_t len,
			const char *content_type, const char *secret,
			struct cs_problems *pr)
{
	memset(pr, 0, sizeof *pr);
	if (len == 0)
		return cs_error(CS_EDATA, "the response is empty");
	char ex[400];
	const char *end = NULL;
	cJSON *j = cJSON_ParseWithLengthOpts(body, len, &end, 0);
	if (j == NULL) {
		if (cs_fetch_is_html(body, len, content_type)) {
			cs_fetch_excerpt(body, len, secret, 200, ex, sizeof ex);
			return cs_error_redacted(CS_EDATA, secret, "the response is HTML, not JSON: %s", ex);
		}
		const char *kind = binary_kind(body, len);
		if (kind != NULL) /* never raw bytes on a terminal */
			return cs_error(CS_EDATA, "the response is not JSON: it looks like "
					"%s (%zu bytes)", kind, len);
		cs_fetch_excerpt(body, len, secret, 100, ex, sizeof ex);
		if (cs_json_cut_short(body, len, len))
			return cs_error_redacted(CS_EDATA, secret, "the response is not valid JSON (it "
				    "ends early, at byte %zu): %s", len, ex);
		size_t at = end && end >= body && end <= body + len ? (size_t)(end - body) : 0;
		return cs_error_redacted(CS_EDATA, secret, "the response is not valid JSON (error "
			    "at byte %zu of %zu): %s", at, len, ex);
	}
	cJSON_Delete(j);
	enum cs_provider got;
	if (expect >= 0 && cs_provider_detect(body, len, &got) == CS_OK &&
	    (int)got != expect)
		return cs_error(CS_EDATA, "expected %s data, got %s data",
				cs_mbfetch_provider_name((enum cs_provider)expect),
				cs_mbfetch_provider_name(got));
	if (cs_provider_check(body, len, pr) == CS_OK)
		return CS_OK;
	int kept = pr->count < 32 ? pr->count : 32;
	for (int i = 0; i < kept; i++)
		cs_redact(pr->msg[i], sizeof pr->msg[i], secret);
	if (kept == 0)
		return cs_error_redacted(CS_EDATA, secret, "invalid data: %s", cs_errmsg());
	return cs_error(CS_EDATA, "invalid data: %d problem%s", pr->count,
			pr->count == 1 ? "" : "s");
}

int cs_mbfetch_check(const char *path, size_t max_bytes, struct cs_problems *pr,
		     char *summary, size_t size)
{
	memset(pr, 0, sizeof *pr);
	summary[0] = '\0';
	unsigned char *data = NULL;
	size_t len = 0;
	int rc = cs_read_all(path, max_bytes, &data, &len);
	if (rc != CS_OK)
		return rc == CS_EDATA ? rc : CS_EIO;
	rc = cs_mbfetch_validate(-1, (const char *)data, len, NULL, NULL, pr);
	if (rc == CS_OK) {
		struct cs_series s;
		if (cs_provider_parse((const char *)data, len, path, &s) == CS_OK) {
			char t0[32] = "", t1[32] = "";
			if (s.n > 0) {
				cs_time_format(s.time_utc[0], t0, sizeof t0);
				cs_time_format(s.time_utc[s.n - 1], t1, sizeof t1);
			}
			snprintf(summary, size, "%s, %d hour%s, %s to %s",
				 cs_mbfetch_provider_name(s.provider), s.n, s.n == 1 ? "" : "s",
				 t0, t1);
			cs_series_free(&s);
		} else {
			rc = CS_EDATA;
		}
	}
	free(data);
	return rc;
}
