/* The fetching side of mbfetch (see mbfetch.h): judging answers, retrying,
 * validating, the cache, writing. */
#include "apps/mbfetch_run.h"

#include "core/err.h"
#include "core/fileio.h"
#include "core/time.h"

#include <cjson/cJSON.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#ifndef CS_VERSION
#define CS_VERSION "unknown"
#endif

/* Formats into buf and redacts the secret from it. */
static void vredacted(char *buf, size_t size, const char *secret, const char *fmt,
		      va_list ap) __attribute__((format(printf, 4, 0)));
static void vredacted(char *buf, size_t size, const char *secret, const char *fmt,
		      va_list ap)
{
	vsnprintf(buf, size, fmt, ap);
	cs_redact(buf, size, secret);
}

/* Records a message with the secret redacted; returns code. */
static int fail(int code, const char *secret, const char *fmt, ...)
	__attribute__((format(printf, 3, 4)));
static int fail(int code, const char *secret, const char *fmt, ...)
{
	char buf[1024];
	va_list ap;
	va_start(ap, fmt);
	vredacted(buf, sizeof buf, secret, fmt, ap);
	va_end(ap);
	return cs_error(code, "%s", buf);
}

/* Tells the caller's log, with the secret redacted. */
static void say(const struct cs_mbfetch_opts *o, const char *secret, int level,
		const char *fmt, ...) __attribute__((format(printf, 4, 5)));
static void say(const struct cs_mbfetch_opts *o, const char *secret, int level,
		const char *fmt, ...)
{
	if (o->log == NULL)
		return;
	char buf[1024];
	va_list ap;
	va_start(ap, fmt);
	vredacted(buf, sizeof buf, secret, fmt, ap);
	va_end(ap);
	o->log(o->log_user, level, buf);
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

/* 1 when JSON text stops inside a string or with brackets still open: the
 * mark of a cut transfer, whatever the parser stumbled on first. */
static int json_cut_short(const char *s, size_t len)
{
	int depth = 0, in_str = 0;
	for (size_t i = 0; i < len; i++) {
		char c = s[i];
		if (in_str) {
			if (c == '\\')
				i++;
			else if (c == '"')
				in_str = 0;
		} else if (c == '"') {
			in_str = 1;
		} else if (c == '{' || c == '[') {
			depth++;
		} else if (c == '}' || c == ']') {
			depth--;
		}
	}
	return in_str || depth > 0;
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
			return fail(CS_EDATA, secret, "the response is HTML, not JSON: %s", ex);
		}
		cs_fetch_excerpt(body, len, secret, 100, ex, sizeof ex);
		if (json_cut_short(body, len))
			return fail(CS_EDATA, secret, "the response is not valid JSON (it "
				    "ends early, at byte %zu): %s", len, ex);
		size_t at = end && end >= body && end <= body + len ? (size_t)(end - body) : 0;
		return fail(CS_EDATA, secret, "the response is not valid JSON (error "
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
		return fail(CS_EDATA, secret, "invalid data: %s", cs_errmsg());
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

/* ---- cache ---- */

static int cache_path(const struct cs_mbfetch_opts *o, char *path, size_t size)
{
	char url[2048];
	if (cs_mbfetch_url(o, NULL, url, sizeof url) != CS_OK)
		return -1;
	uint64_t h = 1469598103934665603ull; /* FNV-1a 64 */
	for (const unsigned char *p = (const unsigned char *)url; *p; p++)
		h = (h ^ *p) * 1099511628211ull;
	int n = snprintf(path, size, "%s/%s-%016llx.json", o->cache_dir,
			 cs_mbfetch_provider_name(o->provider), (unsigned long long)h);
	return n < 0 || (size_t)n >= size ? -1 : 0;
}

static int write_all(int fd, const char *p, size_t n)
{
	while (n > 0) {
		ssize_t w = write(fd, p, n);
		if (w < 0 && errno == EINTR)
			continue;
		if (w < 0)
			return -1;
		p += w;
		n -= (size_t)w;
	}
	return 0;
}

static int store(const char *path, const char *data, size_t len)
{
	struct cs_outfile of;
	int rc = cs_outfile_open(&of, path);
	if (rc != CS_OK)
		return rc;
	if (write_all(of.fd, data, len) < 0) {
		rc = cs_error(CS_EIO, "cannot write %s: %s", strcmp(path, "-") ? path
			      : "standard output", strerror(errno));
		cs_outfile_abort(&of);
		return rc;
	}
	return cs_outfile_commit(&of);
}

/* A fresh, valid cached response into *data, or nothing. */
static void cache_load(const struct cs_mbfetch_opts *o, const char *path,
		       unsigned char **data, size_t *len)
{
	struct stat st;
	*data = NULL;
	if (stat(path, &st) < 0)
		return;
	double age = difftime(time(NULL), st.st_mtime);
	if (!(age >= -60.0 && age < o->cache_max_age_s)) {
		say(o, NULL, CS_LOG_INFO, "cache %s is %.0f s old: fetching", path, age);
		return;
	}
	struct cs_problems pr;
	if (cs_read_all(path, o->max_bytes, data, len) != CS_OK ||
	    cs_mbfetch_validate((int)o->provider, (const char *)*data, *len, NULL,
				NULL, &pr) != CS_OK) {
		say(o, NULL, CS_LOG_WARN, "ignoring the cache %s: %s", path, cs_errmsg());
		free(*data);
		*data = NULL;
		return;
	}
	say(o, NULL, CS_LOG_INFO, "using the cache %s (%.0f s old)", path, age);
}

/* ---- the run ---- */

static void sleep_s(double s)
{
	struct timespec ts = {(time_t)s, (long)((s - floor(s)) * 1e9)};
	while (nanosleep(&ts, &ts) < 0 && errno == EINTR)
		;
}

static size_t count_occ(const char *s, const char *w)
{
	size_t n = 0, wl = strlen(w);
	for (const char *p = s; wl && (p = strstr(p, w)) != NULL; p += wl)
		n++;
	return n;
}

/* The body with every occurrence of the secret replaced (a new buffer), or
 * NULL when it holds none. */
static char *redact_body(const char *body, size_t *len, const char *secret)
{
	if (secret == NULL || count_occ(body, secret) == 0)
		return NULL;
	size_t cap = *len + count_occ(body, secret) * sizeof CS_REDACTED + 1;
	char *out = malloc(cap);
	if (out == NULL)
		return NULL;
	memcpy(out, body, *len + 1);
	cs_redact(out, cap, secret);
	*len = strlen(out);
	return out;
}

static int is_loopback(const char *url)
{
	const char *h = strstr(url, "://");
	h = h ? h + 3 : url;
	return strncmp(h, "127.", 4) == 0 || strncmp(h, "localhost", 9) == 0 ||
	       strncmp(h, "[::1]", 5) == 0;
}

/* Attempts until a body to validate arrives or it is time to give up. */
static int fetch_loop(const struct cs_mbfetch_opts *o, struct cs_mbfetch_result *res,
		      const char *url, const char *key, const char *key_source,
		      struct cs_fetch_resp *resp)
{
	char ua[64];
	snprintf(ua, sizeof ua, "mbfetch/%s (cloudscape)", CS_VERSION);
	struct cs_fetch_req req = {
		.url = url, .connect_timeout_s = o->connect_timeout_s,
		.timeout_s = o->timeout_s, .max_bytes = o->max_bytes,
		.user_agent = ua, .secret = key,
		.https_only_redirects = strncmp(url, "https:", 6) == 0,
	};
	int total = o->retries + 1;
	for (int a = 1;; a++) {
		res->attempts = a;
		say(o, key, CS_LOG_INFO, "GET %s", res->url);
		cs_fetch_get(&req, resp);
		struct cs_verdict v;
		cs_mbfetch_judge(o->provider, resp, key, &v);
		if (resp->fail == CS_FETCH_OK)
			say(o, key, CS_LOG_INFO, "HTTP %ld, %zu bytes%s%s in %.3f s",
			    resp->status, resp->len, resp->content_type[0] ? ", " : "",
			    resp->content_type, resp->seconds);
		if (v.code == CS_OK)
			return CS_OK;
		cs_fetch_resp_free(resp);
		char tail[64] = "";
		if (a > 1)
			snprintf(tail, sizeof tail, "; gave up after %d attempts", a);
		if (v.code == CS_EAUTH && key_source)
			return fail(v.code, key, "%s%s; the key came from %s", v.msg,
				    tail, key_source);
		if (!v.retry || a >= total)
			return fail(v.code, key, "%s%s", v.msg, tail);
		double wait = o->retry_delay_s * ldexp(1.0, a - 1);
		if (wait > o->retry_max_wait_s)
			wait = o->retry_max_wait_s;
		if (v.wait_s > wait) {
			if (v.wait_s > o->retry_max_wait_s)
				return fail(v.code, key, "%s%s; the server asks to wait "
					    "%.0f s, longer than --retry-max-wait %g s",
					    v.msg, tail, v.wait_s, o->retry_max_wait_s);
			wait = v.wait_s;
		}
		say(o, key, CS_LOG_WARN, "%s; retrying in %.3g s (attempt %d of %d)",
		    v.msg, wait, a + 1, total);
		sleep_s(wait);
	}
}

/* Whether path can be created or replaced: its folder exists and is
 * writable, and it is no folder itself. */
static int output_writable(const char *path)
{
	if (strcmp(path, "-") == 0)
		return CS_OK;
	struct stat st;
	if (stat(path, &st) == 0) {
		if (S_ISDIR(st.st_mode))
			return cs_error(CS_EIO, "cannot write %s: Is a directory", path);
		if (!S_ISREG(st.st_mode))
			return access(path, W_OK) == 0 ? CS_OK
			       : cs_error(CS_EIO, "cannot write %s: %s", path, strerror(errno));
	}
	char dir[4096];
	const char *slash = strrchr(path, '/');
	int n = slash ? snprintf(dir, sizeof dir, "%.*s", (int)(slash - path + 1), path)
		      : snprintf(dir, sizeof dir, ".");
	if (n < 0 || (size_t)n >= sizeof dir)
		return cs_error(CS_EINVAL, "output file name too long");
	if (access(dir, W_OK | X_OK) < 0)
		return cs_error(CS_EIO, "cannot create %s: %s", path, strerror(errno));
	return CS_OK;
}

/* Writes data to the output whole or not at all; the cache too if asked. */
static int finish(const struct cs_mbfetch_opts *o, const char *data, size_t len,
		  const char *cpath)
{
	int rc = store(o->output, data, len);
	if (rc == CS_OK && cpath) {
		if (mkdir(o->cache_dir, 0700) < 0 && errno != EEXIST)
			say(o, NULL, CS_LOG_WARN, "cannot create the cache %s: %s",
			    o->cache_dir, strerror(errno));
		else if (store(cpath, data, len) != CS_OK)
			say(o, NULL, CS_LOG_WARN, "cannot cache: %s", cs_errmsg());
	}
	return rc;
}

int cs_mbfetch_run(const struct cs_mbfetch_opts *o, struct cs_mbfetch_result *res)
{
	memset(res, 0, sizeof *res);
	int rc = cs_mbfetch_check_opts(o);
	if (rc != CS_OK)
		return rc;
	char key[CS_MBFETCH_KEY_MAX + 1] = "", source[4200] = "";
	int need_key = o->provider == CS_PROVIDER_METEOBLUE;
	if (need_key && o->dry_run)
		strcpy(key, CS_REDACTED);
	else if (need_key && (rc = cs_mbfetch_key(o->key_file, key, sizeof key,
						  source, sizeof source)) != CS_OK)
		return rc;
	const char *secret = need_key ? key : NULL;
	char url[2048];
	if ((rc = cs_mbfetch_url(o, need_key ? key : NULL, url, sizeof url)) != CS_OK)
		return rc;
	snprintf(res->url, sizeof res->url, "%s", url);
	cs_redact(res->url, sizeof res->url, secret);
	if (o->dry_run)
		return CS_OK;
	if (need_key && strncmp(url, "http:", 5) == 0 && !is_loopback(url))
		say(o, secret, CS_LOG_WARN, "sending the API key unencrypted over http");

	/* no request (and no credit spent) for a destination that cannot be
	 * written; the temporary itself is created only once there is
	 * something to write, so an interrupted wait leaves nothing behind */
	if ((rc = output_writable(o->output)) != CS_OK)
		return rc;
	char cpath[4200];
	int use_cache = o->cache_dir && cache_path(o, cpath, sizeof cpath) == 0;
	if (use_cache) {
		unsigned char *data;
		size_t len;
		cache_load(o, cpath, &data, &len);
		if (data) {
			res->from_cache = 1;
			rc = finish(o, (const char *)data, len, NULL);
			free(data);
			return rc;
		}
	}
	struct cs_fetch_resp resp;
	rc = fetch_loop(o, res, url, secret, need_key ? source : NULL, &resp);
	if (rc != CS_OK)
		return rc;
	rc = cs_mbfetch_validate((int)o->provider, resp.body, resp.len,
				 resp.content_type, secret, &res->problems);
	if (rc != CS_OK) {
		char why[1024];
		snprintf(why, sizeof why, "%s", cs_errmsg());
		rc = fail(rc, secret, "%s (HTTP %ld, %zu bytes): %s",
			  cs_mbfetch_provider_name(o->provider), resp.status, resp.len, why);
		cs_fetch_resp_free(&resp);
		return rc;
	}
	size_t len = resp.len;
	char *clean = redact_body(resp.body, &len, secret);
	if (clean)
		say(o, secret, CS_LOG_WARN, "the response held the API key; it was "
		    "replaced by %s", CS_REDACTED);
	rc = finish(o, clean ? clean : resp.body, len, use_cache ? cpath : NULL);
	free(clean);
	cs_fetch_resp_free(&resp);
	return rc;
}
