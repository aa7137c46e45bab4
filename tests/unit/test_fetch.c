/* Fetching without a network: query strings, redaction, excerpts of error
 * bodies, what each answer means (retry or not, how long to wait), the
 * request URLs, the key's sources, and validation messages. */
#include "test.h"

#include "core/err.h"
#include "net/http.h"
#include "apps/mbfetch_run.h"

#include <math.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <unistd.h>

#define KEY "s3cr3tKEY/+x"

static void query_add_percent_encodes_values(void)
{
	char url[128] = "https://h/p";
	CHECK(cs_query_add(url, sizeof url, "a", "x y&z=é", NULL) == CS_OK);
	CHECK(cs_query_add(url, sizeof url, "list", "a,b,c", ",") == CS_OK);
	CHECK(cs_query_add(url, sizeof url, "safe", "A-z_0.9~", NULL) == CS_OK);
	CHECK(strcmp(url, "https://h/p?a=x%20y%26z%3D%C3%A9&list=a,b,c&safe=A-z_0.9~") == 0);
	char small[24] = "https://h/p?a=1";
	CHECK(cs_query_add(small, sizeof small, "name", "too long for it", NULL) == CS_EINVAL);
	CHECK(strcmp(small, "https://h/p?a=1") == 0);
}

static void redact_replaces_plain_and_encoded_secret(void)
{
	char s[128] = "key " KEY " and s3cr3tKEY%2F%2Bx and again " KEY;
	cs_redact(s, sizeof s, KEY);
	CHECK(strcmp(s, "key REDACTED and REDACTED and again REDACTED") == 0);
	char t[16] = "k=" KEY;
	cs_redact(t, sizeof t, KEY);
	CHECK(strcmp(t, "k=REDACTED") == 0);
	char u[8] = "ab";
	cs_redact(u, sizeof u, NULL);
	CHECK(strcmp(u, "ab") == 0);
}

static void excerpt_reduces_html_and_escapes_controls(void)
{
	char out[256];
	const char *html = "<!DOCTYPE html>\n<html><head><title>502 Bad Gateway</title>"
			   "<style>p{color:red}</style></head>\n<body><!-- x -->"
			   "<h1>502   Bad\tGateway</h1><p>a &amp; b &lt;c&gt;</p></body></html>";
	cs_fetch_excerpt(html, strlen(html), NULL, 300, out, sizeof out);
	CHECK(strcmp(out, "502 Bad Gateway 502 Bad Gateway a & b <c>") == 0);
	const char bin[] = "bad\x1b[31mred\x7f\xff ok \xc2\xb0" "C";
	cs_fetch_excerpt(bin, sizeof bin - 1, NULL, 300, out, sizeof out);
	CHECK(strcmp(out, "bad\\x1b[31mred\\x7f\\xff ok \xc2\xb0" "C") == 0);
	cs_fetch_excerpt("abcdefghij", 10, NULL, 4, out, sizeof out);
	CHECK(strcmp(out, "abcd...") == 0);
	const char *echo = "{\"error_message\":\"bad key " KEY "\"}";
	cs_fetch_excerpt(echo, strlen(echo), KEY, 300, out, sizeof out);
	CHECK(strstr(out, "s3cr3t") == NULL);
	CHECK_STR_CONTAINS(out, "bad key REDACTED");
	CHECK(cs_fetch_is_html("  <html>", 8, NULL) && !cs_fetch_is_html("{}", 2, NULL));
	CHECK(cs_fetch_is_html("x", 1, "text/html; charset=utf-8"));
}

static void excerpt_of_a_long_body_shows_no_part_of_the_secret(void)
{
	/* the secret straddles the 64 KiB window the excerpt looks at */
	size_t n = 70000;
	char *body = malloc(n + 1);
	memset(body, ' ', n);
	memcpy(body + 65536 - 4, KEY, strlen(KEY));
	body[n] = '\0';
	char out[256];
	cs_fetch_excerpt(body, n, KEY, 300, out, sizeof out);
	CHECK(strstr(out, "s3cr") == NULL);
	free(body);
}

static struct cs_verdict judge(enum cs_provider p, long status, const char *body,
			       double retry_after)
{
	struct cs_fetch_resp r;
	memset(&r, 0, sizeof r);
	r.status = status;
	r.body = (char *)body;
	r.len = strlen(body);
	r.retry_after_s = retry_after;
	struct cs_verdict v;
	cs_mbfetch_judge(p, &r, KEY, &v);
	return v;
}

static void judge_maps_statuses_and_bodies_to_outcomes(void)
{
	const enum cs_provider MB = CS_PROVIDER_METEOBLUE, OM = CS_PROVIDER_OPENMETEO;
	struct cs_verdict v = judge(MB, 200, "{\"metadata\":{}}", -1);
	CHECK(v.code == CS_OK);
	v = judge(MB, 200, "{\"error_message\":\"MB_REQUEST::DISPATCH: This datafeed is "
		  "not authorized for your api key\"}", -1);
	CHECK(v.code == CS_EAUTH && !v.retry);
	v = judge(MB, 401, "{\"error_message\":\"MB_REQUEST::DISPATCH: Invalid api key "
		  "apikey=" KEY "\"}", -1);
	CHECK(v.code == CS_EAUTH && !v.retry);
	CHECK_STR_CONTAINS(v.msg, "HTTP 401 Unauthorized): MB_REQUEST::DISPATCH: Invalid api key apikey=REDACTED");
	v = judge(MB, 403, "forbidden", -1);
	CHECK(v.code == CS_EAUTH && !v.retry);
	v = judge(OM, 400, "{\"error\":true,\"reason\":\"Cannot initialize X\"}", -1);
	CHECK(v.code == CS_EREQUEST && !v.retry);
	CHECK_STR_CONTAINS(v.msg, "request rejected (open-meteo, HTTP 400 Bad Request): Cannot initialize X");
	v = judge(MB, 404, "<html><body>Not here</body></html>", -1);
	CHECK(v.code == CS_EREQUEST && !v.retry);
	CHECK_STR_CONTAINS(v.msg, "Not here");
	v = judge(OM, 429, "{\"error\":true,\"reason\":\"Daily API request limit exceeded.\"}", -1);
	CHECK(v.code == CS_ERATE && !v.retry);
	v = judge(OM, 429, "{\"error\":true,\"reason\":\"Hourly API request limit exceeded.\"}", -1);
	CHECK(v.code == CS_ERATE && !v.retry);
	v = judge(OM, 429, "{\"error\":true,\"reason\":\"Minutely API request limit exceeded.\"}", -1);
	CHECK(v.code == CS_ERATE && v.retry && v.wait_s == 60.0);
	v = judge(OM, 429, "{\"error\":true,\"reason\":\"Too many concurrent requests\"}", -1);
	CHECK(v.code == CS_ERATE && v.retry && v.wait_s < 0);
	v = judge(MB, 429, "", 7);
	CHECK(v.code == CS_ERATE && v.retry && v.wait_s == 7.0);
	CHECK_STR_CONTAINS(v.msg, "(empty body)");
	v = judge(MB, 503, "down", 2);
	CHECK(v.code == CS_ENET && v.retry && v.wait_s == 2.0);
	v = judge(MB, 500, "oops", -1);
	CHECK(v.code == CS_ENET && v.retry && v.wait_s < 0);
	v = judge(MB, 408, "", -1);
	CHECK(v.code == CS_ENET && v.retry);
	v = judge(MB, 302, "", -1);
	CHECK(v.code == CS_EREQUEST && !v.retry);
}

static void judge_classifies_failed_transfers(void)
{
	struct cs_fetch_resp r;
	struct cs_verdict v;
	static const struct { enum cs_fetch_fail f; int code, retry; } cases[] = {
		{CS_FETCH_TIMEOUT, CS_ENET, 1}, {CS_FETCH_CONNECT, CS_ENET, 1},
		{CS_FETCH_TOO_BIG, CS_EDATA, 0}, {CS_FETCH_TLS, CS_ENET, 0},
		{CS_FETCH_OTHER, CS_ENET, 0},
	};
	for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
		memset(&r, 0, sizeof r);
		r.fail = cases[i].f;
		snprintf(r.error, sizeof r.error, "failed for apikey=%s", KEY);
		cs_mbfetch_judge(CS_PROVIDER_METEOBLUE, &r, KEY, &v);
		CHECK(v.code == cases[i].code && v.retry == cases[i].retry);
		CHECK(strstr(v.msg, KEY) == NULL);
	}
}

static void url_holds_what_cloudscape_needs(void)
{
	struct cs_mbfetch_opts o;
	char url[2048];
	cs_mbfetch_defaults(&o);
	o.base_url = "http://127.0.0.1:9/mirror/";
	o.name = "Bern Nord";
	o.days = 3;
	o.history_days = 1;
	CHECK(cs_mbfetch_url(&o, KEY, url, sizeof url) == CS_OK);
	CHECK(strcmp(url, "http://127.0.0.1:9/mirror/packages/basic-1h_clouds-1h?"
		     "lat=46.94798&lon=7.44743&asl=540&name=Bern%20Nord&tz=UTC&format=json"
		     "&temperature=C&windspeed=ms-1&winddirection=degree"
		     "&precipitationamount=mm&forecast_days=3&history_days=1"
		     "&apikey=s3cr3tKEY%2F%2Bx") == 0);
	o.provider = CS_PROVIDER_OPENMETEO;
	o.base_url = NULL;
	o.asl_m = NAN;
	o.lat_deg = -0.000001;
	o.lon_deg = 7.5;
	CHECK(cs_mbfetch_url(&o, NULL, url, sizeof url) == CS_OK);
	CHECK(strcmp(url, "https://api.open-meteo.com/v1/forecast?latitude=0&longitude=7.5"
		     "&hourly=cloud_cover,cloud_cover_low,cloud_cover_mid,cloud_cover_high,"
		     "precipitation,showers,snowfall,wind_speed_10m,wind_direction_10m,visibility,"
		     "relative_humidity_2m,temperature_2m,is_day&temperature_unit=celsius"
		     "&wind_speed_unit=ms&precipitation_unit=mm&timezone=GMT&past_days=1"
		     "&forecast_days=3") == 0);
	/* --radiation: the instant irradiances (cloud_cover is there already) */
	o.radiation = 1;
	CHECK(cs_mbfetch_url(&o, NULL, url, sizeof url) == CS_OK);
	CHECK_STR_CONTAINS(url, "temperature_2m,is_day,shortwave_radiation_instant,"
			   "direct_normal_irradiance_instant,diffuse_radiation_instant"
			   "&temperature_unit=celsius");
	o.provider = CS_PROVIDER_METEOBLUE;
	CHECK(cs_mbfetch_url(&o, NULL, url, sizeof url) == CS_OK);
	CHECK_STR_CONTAINS(url, "https://my.meteoblue.com/packages/"
			   "basic-1h_clouds-1h_solar-1h?lat=0&lon=7.5&");
}

static void run_rejects_bad_options_before_any_request(void)
{
	struct cs_mbfetch_opts o;
	struct cs_mbfetch_result r;
	cs_mbfetch_defaults(&o);
	o.dry_run = 1;
	o.days = 8;
	CHECK(cs_mbfetch_run(&o, &r) == CS_EINVAL);
	CHECK_STR_CONTAINS(cs_errmsg(), "--days: 8 is out of range 1..7 for meteoblue");
	o.days = 3;
	o.base_url = "ftp://example.org";
	CHECK(cs_mbfetch_run(&o, &r) == CS_EINVAL);
	o.base_url = NULL;
	o.provider = CS_PROVIDER_OPENMETEO;
	o.history_days = 93;
	CHECK(cs_mbfetch_run(&o, &r) == CS_EINVAL);
	o.history_days = 92;
	CHECK(cs_mbfetch_run(&o, &r) == CS_OK);
	CHECK_STR_CONTAINS(r.url, "past_days=92");
}

static void key_comes_from_file_env_or_nowhere(void)
{
	char key[300], src[4200], path[] = "/tmp/cs-test-key.XXXXXX";
	int fd = mkstemp(path);
	CHECK(fd >= 0);
	CHECK(write(fd, "  " KEY " \nsecond line\n", strlen(KEY) + 16) > 0);
	close(fd);
	CHECK(cs_mbfetch_key(path, key, sizeof key, src, sizeof src) == CS_OK);
	CHECK(strcmp(key, KEY) == 0 && strcmp(src, path) == 0);
	chmod(path, 0604);
	CHECK(cs_mbfetch_key(path, key, sizeof key, src, sizeof src) == CS_EAUTH);
	CHECK_STR_CONTAINS(cs_errmsg(), "(mode 0604)");
	CHECK(strstr(cs_errmsg(), KEY) == NULL);
	chmod(path, 0400);
	CHECK(cs_mbfetch_key(path, key, sizeof key, src, sizeof src) == CS_OK);
	unlink(path);
	setenv("MBFETCH_APIKEY", "envkey123", 1);
	CHECK(cs_mbfetch_key(NULL, key, sizeof key, src, sizeof src) == CS_OK);
	CHECK(strcmp(key, "envkey123") == 0 && strcmp(src, "MBFETCH_APIKEY") == 0);
	setenv("MBFETCH_APIKEY", "two words", 1);
	CHECK(cs_mbfetch_key(NULL, key, sizeof key, src, sizeof src) == CS_EAUTH);
	unsetenv("MBFETCH_APIKEY");
	setenv("HOME", "/nonexistent-cs-home", 1);
	unsetenv("XDG_CONFIG_HOME");
	CHECK(cs_mbfetch_key(NULL, key, sizeof key, src, sizeof src) == CS_EAUTH);
	CHECK_STR_CONTAINS(cs_errmsg(), "no API key");
}

static void validate_says_what_a_body_is_instead(void)
{
	struct cs_problems pr;
	CHECK(cs_mbfetch_validate(-1, "{\"a\": [1, 2", 11, NULL, NULL, &pr) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "ends early, at byte 11");
	CHECK(cs_mbfetch_validate(-1, "{\"a\": x}", 8, NULL, NULL, &pr) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "error at byte");
	CHECK(cs_mbfetch_validate(-1, "<html>" KEY "</html>", 6 + strlen(KEY) + 7,
				  NULL, KEY, &pr) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "HTML, not JSON: REDACTED");
	CHECK(cs_mbfetch_validate(-1, "", 0, NULL, NULL, &pr) == CS_EDATA);
}

static void sites_are_found_by_name_in_any_case(void)
{
	const struct cs_place *s = cs_place_find("gURTEN");
	CHECK(s != NULL && strcmp(s->name, "Gurten") == 0);
	CHECK(s && fabs(s->lat_deg - 46.917) < 0.01 && s->alt_m > 800);
	CHECK(cs_place_find("Atlantis") == NULL);
	int n;
	cs_places(&n);
	CHECK(n >= 5);
}

/* The cases, in the order they run: their number is the plan. */
static const struct t_case t_cases[] = {
	CASE(query_add_percent_encodes_values),
	CASE(redact_replaces_plain_and_encoded_secret),
	CASE(excerpt_reduces_html_and_escapes_controls),
	CASE(excerpt_of_a_long_body_shows_no_part_of_the_secret),
	CASE(judge_maps_statuses_and_bodies_to_outcomes),
	CASE(judge_classifies_failed_transfers),
	CASE(url_holds_what_cloudscape_needs),
	CASE(run_rejects_bad_options_before_any_request),
	CASE(key_comes_from_file_env_or_nowhere),
	CASE(validate_says_what_a_body_is_instead),
	CASE(sites_are_found_by_name_in_any_case),
};

int main(void)
{
	T_RUN_TABLE(t_cases);
	TEST_EXIT();
}
