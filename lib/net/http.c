#include "net/http.h"

#include "core/err.h"

#include <curl/curl.h>
#include <ctype.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

static pthread_once_t global_once = PTHREAD_ONCE_INIT;
static CURLcode global_rc = CURLE_OK;

static void global_init(void)
{
	global_rc = curl_global_init(CURL_GLOBAL_DEFAULT);
}

int cs_fetch_global_init(void)
{
	pthread_once(&global_once, global_init);
	if (global_rc != CURLE_OK)
		return cs_error(CS_ENET, "cannot initialise libcurl: %s",
				curl_easy_strerror(global_rc));
	return CS_OK;
}

/* ---- query strings and redaction ---- */

static int unreserved(int c, const char *keep)
{
	return isalnum(c) || c == '-' || c == '.' || c == '_' || c == '~' ||
	       (keep && c != '\0' && strchr(keep, c) != NULL);
}

/* Percent-encodes s into out; returns the encoded length (which may exceed
 * size, like snprintf). */
static size_t encode(const char *s, const char *keep, char *out, size_t size)
{
	static const char hex[] = "0123456789ABCDEF";
	size_t n = 0;
	for (const unsigned char *p = (const unsigned char *)s; *p; p++) {
		if (unreserved(*p, keep)) {
			if (n + 1 < size)
				out[n] = (char)*p;
			n++;
		} else {
			if (n + 3 < size) {
				out[n] = '%';
				out[n + 1] = hex[*p >> 4];
				out[n + 2] = hex[*p & 15];
			}
			n += 3;
		}
	}
	if (size > 0)
		out[n < size ? n : size - 1] = '\0';
	return n;
}

int cs_query_add(char *buf, size_t size, const char *name, const char *value,
		 const char *keep)
{
	size_t used = strlen(buf);
	const char *sep = strchr(buf, '?') ? "&" : "?";
	int n = snprintf(buf + used, size - used, "%s%s=", sep, name);
	if (n < 0 || (size_t)n >= size - used) {
		buf[used] = '\0';
		return cs_error(CS_EINVAL, "URL too long");
	}
	used += (size_t)n;
	if (encode(value, keep, buf + used, size - used) >= size - used) {
		buf[used - (size_t)n] = '\0';
		return cs_error(CS_EINVAL, "URL too long");
	}
	return CS_OK;
}

static void replace_all(char *s, size_t size, const char *what)
{
	size_t wl = strlen(what), rl = strlen(CS_REDACTED);
	if (wl == 0)
		return;
	char *p = s;
	while ((p = strstr(p, what)) != NULL) {
		size_t tail = strlen(p + wl);
		size_t at = (size_t)(p - s);
		/* room for the replacement and the tail, cut at size - 1 */
		size_t room = size - 1 - at;
		size_t r = rl < room ? rl : room;
		size_t t = tail < room - r ? tail : room - r;
		memmove(p + r, p + wl, t);
		memcpy(p, CS_REDACTED, r);
		p[r + t] = '\0';
		p += r;
	}
}

void cs_redact(char *s, size_t size, const char *secret)
{
	if (secret == NULL || secret[0] == '\0' || size == 0)
		return;
	replace_all(s, size, secret);
	char enc[1024];
	if (encode(secret, NULL, enc, sizeof enc) < sizeof enc &&
	    strcmp(enc, secret) != 0)
		replace_all(s, size, enc);
}

/* ---- excerpts of bodies ---- */

int cs_fetch_is_html(const char *body, size_t len, const char *content_type)
{
	if (content_type && strncasecmp(content_type, "text/html", 9) == 0)
		return 1;
	size_t i = 0;
	while (i < len && isspace((unsigned char)body[i]))
		i++;
	return i + 1 < len && body[i] == '<' &&
	       (isalpha((unsigned char)body[i + 1]) || body[i + 1] == '!');
}

/* Length of a valid UTF-8 sequence at p (at most n bytes) that is not a C1
 * control, or 0. */
static size_t utf8_len(const unsigned char *p, size_t n)
{
	size_t k = p[0] >= 0xf0 && p[0] <= 0xf4 ? 4 : p[0] >= 0xe0 ? 3
		 : p[0] >= 0xc2 && p[0] < 0xe0 ? 2 : 0;
	if (k == 0 || k > n)
		return 0;
	for (size_t i = 1; i < k; i++)
		if ((p[i] & 0xc0) != 0x80)
			return 0;
	if (p[0] == 0xc2 && p[1] < 0xa0) /* U+0080..U+009F: C1 controls */
		return 0;
	return k;
}

static const struct { const char *name; char c; } entities[] = {
	{"&amp;", '&'}, {"&lt;", '<'}, {"&gt;", '>'}, {"&quot;", '"'},
	{"&#39;", '\''}, {"&apos;", '\''}, {"&nbsp;", ' '},
};

/* Drops tags, comments, and script/style contents; decodes a few entities. */
static size_t strip_html(char *s, size_t len)
{
	size_t o = 0;
	for (size_t i = 0; i < len;) {
		if (s[i] == '<') {
			int skip_body = strncasecmp(s + i, "<script", 7) == 0 ||
					strncasecmp(s + i, "<style", 6) == 0;
			const char *close = skip_body ? (tolower((unsigned char)s[i + 2]) == 'c'
							 ? "</script" : "</style") : ">";
			if (strncmp(s + i, "<!--", 4) == 0)
				close = "-->";
			char *e = strstr(s + i + 1, close);
			if (e == NULL)
				break;
			i = (size_t)(e - s) + strlen(close);
			if (skip_body) {
				char *gt = strchr(s + i, '>');
				i = gt ? (size_t)(gt - s) + 1 : len;
			}
			s[o++] = ' ';
			continue;
		}
		if (s[i] == '&') {
			size_t k = 0;
			for (; k < sizeof entities / sizeof entities[0]; k++)
				if (strncmp(s + i, entities[k].name, strlen(entities[k].name)) == 0)
					break;
			if (k < sizeof entities / sizeof entities[0]) {
				s[o++] = entities[k].c;
				i += strlen(entities[k].name);
				continue;
			}
		}
		s[o++] = s[i++];
	}
	s[o] = '\0';
	return o;
}

/* A window cut from a longer body may end in the first part of the
 * secret: drop it. */
static void drop_partial_secret(char *s, const char *secret)
{
	if (secret == NULL)
		return;
	char enc[1024];
	encode(secret, NULL, enc, sizeof enc);
	const char *forms[2] = {secret, enc};
	for (int f = 0; f < 2; f++) {
		size_t n = strlen(s), k = strlen(forms[f]);
		for (size_t j = k > n ? n : k - (k > 0); j > 0; j--)
			if (strncmp(s + n - j, forms[f], j) == 0) {
				s[n - j] = '\0';
				break;
			}
	}
}

void cs_fetch_excerpt(const char *body, size_t len, const char *secret,
		      size_t max, char *out, size_t outsize)
{
	if (outsize == 0)
		return;
	out[0] = '\0';
	/* a message needs only the start of a body; redact that window before
	 * anything else, with room for replacements longer than the secret */
	int cut = len > 65536;
	if (cut)
		len = 65536;
	size_t cap = len * (strlen(CS_REDACTED) + 1) + 1;
	char *s = malloc(cap);
	if (s == NULL) {
		snprintf(out, outsize, "(%zu bytes)", len);
		return;
	}
	memcpy(s, body, len);
	s[len] = '\0';
	for (size_t i = 0; i < len; i++)
		if (s[i] == '\0')
			s[i] = ' ';
	if (cut)
		drop_partial_secret(s, secret);
	cs_redact(s, cap, secret);
	len = strlen(s);
	if (cs_fetch_is_html(s, len, NULL))
		len = strip_html(s, len);
	size_t o = 0, shown = 0;
	int space = 1;
	for (size_t i = 0; i < len && o + 8 < outsize; i++) {
		unsigned char c = (unsigned char)s[i];
		if (c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v') {
			if (!space)
				out[o++] = ' ';
			space = 1;
			continue;
		}
		space = 0;
		if (shown >= max) {
			o += (size_t)snprintf(out + o, outsize - o, "...");
			break;
		}
		size_t k = c >= 0x80 ? utf8_len((const unsigned char *)s + i, len - i) : 0;
		if (k > 0) {
			if (o + k + 1 >= outsize)
				break;
			memcpy(out + o, s + i, k);
			o += k;
			i += k - 1;
		} else if (c < 0x20 || c >= 0x7f) {
			o += (size_t)snprintf(out + o, outsize - o, "\\x%02x", c);
		} else {
			out[o++] = (char)c;
		}
		shown++;
	}
	while (o > 0 && out[o - 1] == ' ')
		o--;
	out[o] = '\0';
	free(s);
	cs_redact(out, outsize, secret);
}

/* ---- the transfer ---- */

struct sink {
	char *buf;
	size_t len, cap, max;
	int too_big;
};

static size_t on_data(char *p, size_t sz, size_t n, void *user)
{
	struct sink *s = user;
	size_t k = sz * n;
	if (k > s->max - s->len) {
		s->too_big = 1;
		return 0; /* aborts the transfer with CURLE_WRITE_ERROR */
	}
	if (s->len + k + 1 > s->cap) {
		size_t cap = s->cap ? s->cap : 16384;
		while (cap < s->len + k + 1)
			cap *= 2;
		char *nb = realloc(s->buf, cap);
		if (nb == NULL)
			return 0;
		s->buf = nb;
		s->cap = cap;
	}
	memcpy(s->buf + s->len, p, k);
	s->len += k;
	s->buf[s->len] = '\0';
	return k;
}

static enum cs_fetch_fail classify(CURLcode c, int too_big)
{
	switch (c) {
	case CURLE_OK:
		return CS_FETCH_OK;
	case CURLE_OPERATION_TIMEDOUT:
		return CS_FETCH_TIMEOUT;
	case CURLE_COULDNT_RESOLVE_HOST:
	case CURLE_COULDNT_RESOLVE_PROXY:
	case CURLE_COULDNT_CONNECT:
	case CURLE_PARTIAL_FILE:
	case CURLE_RECV_ERROR:
	case CURLE_SEND_ERROR:
	case CURLE_GOT_NOTHING:
	case CURLE_HTTP2:
	case CURLE_HTTP2_STREAM:
	case CURLE_BAD_CONTENT_ENCODING:
	case CURLE_WEIRD_SERVER_REPLY:
		return CS_FETCH_CONNECT;
	case CURLE_FILESIZE_EXCEEDED:
		return CS_FETCH_TOO_BIG;
	case CURLE_WRITE_ERROR:
		return too_big ? CS_FETCH_TOO_BIG : CS_FETCH_OTHER;
	case CURLE_SSL_CONNECT_ERROR:
	case CURLE_PEER_FAILED_VERIFICATION:
	case CURLE_SSL_CERTPROBLEM:
	case CURLE_SSL_CIPHER:
	case CURLE_SSL_CACERT_BADFILE:
	case CURLE_SSL_ENGINE_NOTFOUND:
		return CS_FETCH_TLS;
	default:
		return CS_FETCH_OTHER;
	}
}

static CURLcode setup(CURL *h, const struct cs_fetch_req *req, struct sink *sink,
		      char *errbuf, struct curl_slist *headers)
{
	CURLcode c = CURLE_OK;
#define SET(opt, val) if (c == CURLE_OK) c = curl_easy_setopt(h, opt, val)
	SET(CURLOPT_URL, req->url);
	SET(CURLOPT_NOSIGNAL, 1L);
	SET(CURLOPT_ERRORBUFFER, errbuf);
	SET(CURLOPT_WRITEFUNCTION, on_data);
	SET(CURLOPT_WRITEDATA, sink);
	SET(CURLOPT_CONNECTTIMEOUT_MS, (long)(req->connect_timeout_s * 1000.0 + 0.5));
	SET(CURLOPT_TIMEOUT_MS, (long)(req->timeout_s * 1000.0 + 0.5));
	SET(CURLOPT_MAXFILESIZE_LARGE, (curl_off_t)req->max_bytes);
	SET(CURLOPT_ACCEPT_ENCODING, "");
	SET(CURLOPT_USERAGENT, req->user_agent ? req->user_agent : "cloudscape");
	SET(CURLOPT_HTTPHEADER, headers);
	SET(CURLOPT_FOLLOWLOCATION, 1L);
	SET(CURLOPT_MAXREDIRS, 5L);
#if LIBCURL_VERSION_NUM >= 0x075500
	SET(CURLOPT_PROTOCOLS_STR, "http,https");
	SET(CURLOPT_REDIR_PROTOCOLS_STR, req->https_only_redirects ? "https" : "http,https");
#else
	SET(CURLOPT_PROTOCOLS, (long)(CURLPROTO_HTTP | CURLPROTO_HTTPS));
	SET(CURLOPT_REDIR_PROTOCOLS, req->https_only_redirects ? (long)CURLPROTO_HTTPS
			: (long)(CURLPROTO_HTTP | CURLPROTO_HTTPS));
#endif
#undef SET
	return c;
}

static void resp_init(struct cs_fetch_resp *r)
{
	memset(r, 0, sizeof *r);
	r->retry_after_s = -1.0;
}

int cs_fetch_get(const struct cs_fetch_req *req, struct cs_fetch_resp *resp)
{
	resp_init(resp);
	int rc = cs_fetch_global_init();
	if (rc != CS_OK) {
		resp->fail = CS_FETCH_OTHER;
		snprintf(resp->error, sizeof resp->error, "%s", cs_errmsg());
		return rc;
	}
	CURL *h = curl_easy_init();
	struct curl_slist *headers = curl_slist_append(NULL, "Accept: application/json");
	if (h == NULL || headers == NULL) {
		curl_easy_cleanup(h);
		curl_slist_free_all(headers);
		resp->fail = CS_FETCH_OTHER;
		snprintf(resp->error, sizeof resp->error, "cannot start libcurl");
		return cs_error(CS_ENOMEM, "%s", resp->error);
	}
	struct sink sink = {.max = req->max_bytes};
	char errbuf[CURL_ERROR_SIZE] = "";
	CURLcode c = setup(h, req, &sink, errbuf, headers);
	if (c == CURLE_OK)
		c = curl_easy_perform(h);
	long status = 0;
	curl_easy_getinfo(h, CURLINFO_RESPONSE_CODE, &status);
	double secs = 0.0;
	curl_easy_getinfo(h, CURLINFO_TOTAL_TIME, &secs);
	resp->seconds = secs;
	resp->fail = classify(c, sink.too_big);
	if (c == CURLE_OK) {
		resp->status = status;
		const char *ct = NULL;
		if (curl_easy_getinfo(h, CURLINFO_CONTENT_TYPE, &ct) == CURLE_OK && ct)
			snprintf(resp->content_type, sizeof resp->content_type, "%s", ct);
		curl_off_t ra = -1;
		if (curl_easy_getinfo(h, CURLINFO_RETRY_AFTER, &ra) == CURLE_OK && ra > 0)
			resp->retry_after_s = (double)ra;
		if (sink.buf == NULL)
			sink.buf = calloc(1, 1);
		if (sink.buf == NULL) {
			resp->fail = CS_FETCH_OTHER;
			c = CURLE_OUT_OF_MEMORY;
		}
	}
	if (resp->fail == CS_FETCH_TOO_BIG) {
		snprintf(resp->error, sizeof resp->error,
			 "the response is larger than %zu bytes (--max-bytes); "
			 "transfer aborted", req->max_bytes);
	} else if (resp->fail != CS_FETCH_OK) {
		snprintf(resp->error, sizeof resp->error, "%s",
			 errbuf[0] ? errbuf : curl_easy_strerror(c));
		size_t n = strlen(resp->error);
		while (n > 0 && (resp->error[n - 1] == '\n' || resp->error[n - 1] == '.'))
			resp->error[--n] = '\0';
		cs_redact(resp->error, sizeof resp->error, req->secret);
	}
	curl_slist_free_all(headers);
	curl_easy_cleanup(h);
	if (resp->fail != CS_FETCH_OK) {
		free(sink.buf);
		switch (resp->fail) {
		case CS_FETCH_TOO_BIG:
			return cs_error(CS_EDATA, "%s", resp->error);
		case CS_FETCH_OTHER:
			return cs_error(c == CURLE_URL_MALFORMAT || c == CURLE_UNSUPPORTED_PROTOCOL
					? CS_EINVAL : CS_ENET, "%s", resp->error);
		default:
			return cs_error(CS_ENET, "%s", resp->error);
		}
	}
	resp->body = sink.buf;
	resp->len = sink.len;
	return CS_OK;
}

void cs_fetch_resp_free(struct cs_fetch_resp *resp)
{
	free(resp->body);
	resp->body = NULL;
	resp->len = 0;
}
