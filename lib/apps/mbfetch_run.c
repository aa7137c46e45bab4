/* The mbfetch program (see mbfetch_run.h): options, retrying, the cache,
 * writing; judging and validating answers are net/verdict.h's. */
#include "apps/mbfetch_run.h"

#include "core/err.h"
#include "core/fileio.h"

#include <arpa/inet.h>
#include <errno.h>
#include <netinet/in.h>
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

/* ---- options ---- */

void cs_mbfetch_defaults(struct cs_mbfetch_opts *o)
{
	memset(o, 0, sizeof *o);
	const struct cs_place *bern = cs_place_find("Bern");
	o->provider = CS_PROVIDER_METEOBLUE;
	o->lat_deg = bern->lat_deg;
	o->lon_deg = bern->lon_deg;
	o->asl_m = bern->alt_m;
	o->name = bern->name;
	o->days = -1;
	o->output = "-";
	o->connect_timeout_s = 10.0;
	o->timeout_s = 60.0;
	o->retries = 3;
	o->retry_delay_s = 1.0;
	o->retry_max_wait_s = 120.0;
	o->max_bytes = (size_t)16 << 20;
	o->cache_max_age_s = 3600.0;
}

/* The request part of the options. */
static struct cs_request request_of(const struct cs_mbfetch_opts *o)
{
	struct cs_request r = {
		.provider = o->provider, .lat_deg = o->lat_deg, .lon_deg = o->lon_deg,
		.asl_m = o->asl_m, .name = o->name, .days = o->days,
		.history_days = o->history_days, .base_url = o->base_url,
		.radiation = o->radiation,
	};
	return r;
}

int cs_mbfetch_url(const struct cs_mbfetch_opts *o, const char *key, char *url,
		   size_t size)
{
	struct cs_request r = request_of(o);
	return cs_request_url(&r, key, url, size);
}

int cs_mbfetch_check_opts(const struct cs_mbfetch_opts *o)
{
	/* the base URL last, as the message order has always been */
	struct cs_request r = request_of(o);
	r.base_url = NULL;
	int rc = cs_request_check(&r);
	if (rc != CS_OK)
		return rc;
	if (!(o->connect_timeout_s > 0.0) || !(o->timeout_s > 0.0) ||
	    o->retries < 0 || !(o->retry_delay_s >= 0.0) ||
	    !(o->retry_max_wait_s >= 0.0) || o->max_bytes == 0)
		return cs_error(CS_EINVAL, "timeouts and the size cap must be above 0, "
				"retries and waits at least 0");
	if (o->output == NULL || o->output[0] == '\0')
		return cs_error(CS_EINVAL, "no output file");
	r.base_url = o->base_url;
	return cs_request_check(&r);
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

int cs_mbfetch_is_loopback(const char *url)
{
	const char *h = strstr(url, "://");
	h = h ? h + 3 : url;
	size_t n = strcspn(h, "/?#");
	const char *at = memchr(h, '@', n); /* user:password@host */
	if (at != NULL) {
		n -= (size_t)(at + 1 - h);
		h = at + 1;
	}
	char host[256];
	if (h[0] == '[') { /* [IPv6]:port */
		const char *close = memchr(h, ']', n);
		if (close == NULL || (size_t)(close - h - 1) >= sizeof host)
			return 0;
		memcpy(host, h + 1, (size_t)(close - h - 1));
		host[close - h - 1] = '\0';
		struct in6_addr a6;
		return inet_pton(AF_INET6, host, &a6) == 1 && IN6_IS_ADDR_LOOPBACK(&a6);
	}
	const char *colon = memchr(h, ':', n);
	if (colon != NULL)
		n = (size_t)(colon - h);
	if (n == 0 || n >= sizeof host)
		return 0;
	memcpy(host, h, n);
	host[n] = '\0';
	if (n > 1 && host[n - 1] == '.') /* the root: "localhost." */
		host[n - 1] = '\0';
	if (strcasecmp(host, "localhost") == 0)
		return 1;
	struct in_addr a4; /* 127.0.0.0/8, dotted quad only */
	return inet_pton(AF_INET, host, &a4) == 1 && (ntohl(a4.s_addr) >> 24) == 127;
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
			return cs_error_redacted(v.code, key, "%s%s; the key came from %s%s",
				    v.msg, tail, key_source, o->radiation ?
				    "; the request included meteoblue's solar-1h package "
				    "(--radiation), which the key may not cover: try "
				    "without --radiation" : "");
		if (!v.retry || a >= total)
			return cs_error_redacted(v.code, key, "%s%s", v.msg, tail);
		double wait = o->retry_delay_s * ldexp(1.0, a - 1);
		if (wait > o->retry_max_wait_s)
			wait = o->retry_max_wait_s;
		if (v.wait_s > wait) {
			if (v.wait_s > o->retry_max_wait_s)
				return cs_error_redacted(v.code, key, "%s%s; the server asks to wait "
					    "%.0f s, longer than --retry-max-wait %g s",
					    v.msg, tail, v.wait_s, o->retry_max_wait_s);
			wait = v.wait_s;
		}
		say(o, key, CS_LOG_WARN, "%s; retrying in %.3g s (attempt %d of %d)",
		    v.msg, wait, a + 1, total);
		sleep_s(wait);
	}
}

/* Writes data to the output whole or not at all; the cache too if asked. */
static int finish(const struct cs_mbfetch_opts *o, const char *data, size_t len,
		  const char *cpath)
{
	int rc = cs_write_file_flags(o->output, data, len, o->no_clobber ? CS_OUT_NO_CLOBBER : 0);
	if (rc == CS_OK && cpath) { /* cpath is NULL for what came from the cache */
		if (mkdir(o->cache_dir, 0700) < 0 && errno != EEXIST)
			say(o, NULL, CS_LOG_WARN, "cannot create the cache %s: %s",
			    o->cache_dir, strerror(errno));
		else if (cs_write_file(cpath, data, len) != CS_OK)
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
	if (need_key && strncmp(url, "http:", 5) == 0 && !cs_mbfetch_is_loopback(url))
		say(o, secret, CS_LOG_WARN, "sending the API key unencrypted over http");

	/* no request (and no credit spent) for a destination that cannot be
	 * written; the temporary itself is created only once there is
	 * something to write, so an interrupted wait leaves nothing behind */
	if ((rc = cs_outfile_check(o->output, o->no_clobber ? CS_OUT_NO_CLOBBER : 0)) != CS_OK)
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
		rc = cs_error_redacted(rc, secret, "%s (HTTP %ld, %zu bytes): %s",
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
