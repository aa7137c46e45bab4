/* The request side of a provider fetch (see requests.h). */
#include "net/requests.h"

#include "core/err.h"
#include "net/http.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

#define MB_BASE "https://my.meteoblue.com"
#define OM_BASE "https://api.open-meteo.com"
#define MB_PACKAGES "/packages/basic-1h_clouds-1h"
#define MB_SOLAR "_solar-1h"
#define OM_PATH "/v1/forecast"
#define OM_HOURLY "cloud_cover,cloud_cover_low,cloud_cover_mid,cloud_cover_high," \
	"precipitation,showers,snowfall,wind_speed_10m,wind_direction_10m,visibility," \
	"relative_humidity_2m,temperature_2m,is_day"
#define OM_RADIATION "shortwave_radiation_instant,direct_normal_irradiance_instant," \
	"diffuse_radiation_instant"

const char *cs_mbfetch_provider_name(enum cs_provider p)
{
	return p == CS_PROVIDER_METEOBLUE ? "meteoblue" : "open-meteo";
}

/* ---- the key ---- */

static int key_ok(const char *k)
{
	size_t n = strlen(k);
	if (n == 0 || n > CS_MBFETCH_KEY_MAX)
		return 0;
	for (const char *p = k; *p; p++)
		if (*p <= ' ' || *p >= 0x7f)
			return 0;
	return 1;
}

static int default_key_path(char *path, size_t size)
{
	const char *xdg = getenv("XDG_CONFIG_HOME");
	const char *home = getenv("HOME");
	int n;
	if (xdg && xdg[0] == '/')
		n = snprintf(path, size, "%s/cloudscape/meteoblue.key", xdg);
	else if (home && home[0])
		n = snprintf(path, size, "%s/.config/cloudscape/meteoblue.key", home);
	else
		return -1;
	return n < 0 || (size_t)n >= size ? -1 : 0;
}

int cs_mbfetch_key(const char *key_file, char *key, size_t size, char *source,
		   size_t ssize)
{
	char path[4096];
	static const char om[] = "or use --provider open-meteo, which needs no key";
	if (key_file == NULL) {
		const char *env = getenv("MBFETCH_APIKEY");
		if (env && env[0]) {
			if (!key_ok(env) || strlen(env) >= size)
				return cs_error(CS_EAUTH, "MBFETCH_APIKEY holds no usable key "
						"(1 to %d printable characters, no spaces)", CS_MBFETCH_KEY_MAX);
			strcpy(key, env);
			snprintf(source, ssize, "MBFETCH_APIKEY");
			return CS_OK;
		}
		if (default_key_path(path, sizeof path) < 0)
			return cs_error(CS_EAUTH, "no API key: set MBFETCH_APIKEY, %s", om);
		if (access(path, F_OK) < 0 && errno == ENOENT)
			return cs_error(CS_EAUTH, "no API key: set MBFETCH_APIKEY or write "
					"the key to %s (mode 600), %s", path, om);
		key_file = path;
	}
	int fd = open(key_file, O_RDONLY | O_NOCTTY);
	if (fd < 0)
		return cs_error(CS_EAUTH, "cannot read key file %s: %s", key_file,
				strerror(errno));
	struct stat st;
	char buf[CS_MBFETCH_KEY_MAX + 64];
	ssize_t n = -1;
	int rc = CS_OK;
	if (fstat(fd, &st) < 0)
		rc = cs_error(CS_EAUTH, "cannot read key file %s: %s", key_file,
			      strerror(errno));
	else if (!S_ISREG(st.st_mode))
		rc = cs_error(CS_EAUTH, "key file %s is not a regular file", key_file);
	else if (st.st_mode & 077)
		rc = cs_error(CS_EAUTH, "key file %s is accessible by group or others "
			      "(mode %04o); refusing to use it: run 'chmod 600 %s'",
			      key_file, (unsigned)(st.st_mode & 07777), key_file);
	else if ((n = read(fd, buf, sizeof buf - 1)) < 0)
		rc = cs_error(CS_EAUTH, "cannot read key file %s: %s", key_file,
			      strerror(errno));
	close(fd);
	if (rc != CS_OK)
		return rc;
	buf[n] = '\0';
	buf[strcspn(buf, "\r\n")] = '\0';
	char *k = buf;
	while (*k == ' ' || *k == '\t')
		k++;
	size_t len = strlen(k);
	while (len > 0 && (k[len - 1] == ' ' || k[len - 1] == '\t'))
		k[--len] = '\0';
	if (len == 0)
		return cs_error(CS_EAUTH, "key file %s holds no key on its first line",
				key_file);
	if (!key_ok(k) || len >= size)
		return cs_error(CS_EAUTH, "key file %s holds no usable key (1 to %d "
				"printable characters, no spaces)", key_file, CS_MBFETCH_KEY_MAX);
	strcpy(key, k);
	snprintf(source, ssize, "%s", key_file);
	return CS_OK;
}

/* ---- the request ---- */

/* A number with at most 5 decimals (about 1 m), trailing zeros dropped. */
static void fmt_num(char *buf, size_t size, double v)
{
	snprintf(buf, size, "%.5f", v);
	char *dot = strchr(buf, '.');
	if (dot) {
		char *e = buf + strlen(buf) - 1;
		while (e > dot && *e == '0')
			*e-- = '\0';
		if (e == dot)
			*e = '\0';
	}
	if (strcmp(buf, "-0") == 0)
		strcpy(buf, "0");
}

static int check_base(const char *base)
{
	if (strncmp(base, "https://", 8) != 0 && strncmp(base, "http://", 7) != 0)
		return cs_error(CS_EINVAL, "--base-url %s: must start with https:// "
				"(or http://)", base);
	if (strpbrk(base, "?# \t\r\n"))
		return cs_error(CS_EINVAL, "--base-url %s: must not hold a query, a "
				"fragment or spaces", base);
	return CS_OK;
}

int cs_request_url(const struct cs_request *o, const char *key, char *url,
		   size_t size)
{
	int mb = o->provider == CS_PROVIDER_METEOBLUE;
	const char *base = o->base_url ? o->base_url : mb ? MB_BASE : OM_BASE;
	size_t bl = strlen(base);
	while (bl > 0 && base[bl - 1] == '/')
		bl--;
	int n = snprintf(url, size, "%.*s%s%s", (int)bl, base, mb ? MB_PACKAGES : OM_PATH,
			 mb && o->radiation ? MB_SOLAR : "");
	if (n < 0 || (size_t)n >= size)
		return cs_error(CS_EINVAL, "URL too long");
	char lat[32], lon[32], asl[32], days[16], hist[16];
	fmt_num(lat, sizeof lat, o->lat_deg);
	fmt_num(lon, sizeof lon, o->lon_deg);
	if (!isnan(o->asl_m))
		fmt_num(asl, sizeof asl, o->asl_m);
	snprintf(days, sizeof days, "%d", o->days);
	snprintf(hist, sizeof hist, "%d", o->history_days);
	int rc = CS_OK;
#define ADD(name, value, keep) if (rc == CS_OK) rc = cs_query_add(url, size, name, value, keep)
	if (mb) {
		ADD("lat", lat, NULL);
		ADD("lon", lon, NULL);
		if (!isnan(o->asl_m))
			ADD("asl", asl, NULL);
		if (o->name && o->name[0])
			ADD("name", o->name, NULL);
		ADD("tz", "UTC", NULL);
		ADD("format", "json", NULL);
		ADD("temperature", "C", NULL);
		ADD("windspeed", "ms-1", NULL);
		ADD("winddirection", "degree", NULL);
		ADD("precipitationamount", "mm", NULL);
		if (o->days >= 0)
			ADD("forecast_days", days, NULL);
		if (o->history_days > 0)
			ADD("history_days", hist, NULL);
		if (key)
			ADD("apikey", key, NULL);
	} else {
		ADD("latitude", lat, NULL);
		ADD("longitude", lon, NULL);
		if (!isnan(o->asl_m))
			ADD("elevation", asl, NULL);
		ADD("hourly", o->radiation ? OM_HOURLY "," OM_RADIATION : OM_HOURLY, ",");
		ADD("temperature_unit", "celsius", NULL);
		ADD("wind_speed_unit", "ms", NULL);
		ADD("precipitation_unit", "mm", NULL);
		ADD("timezone", "GMT", NULL);
		if (o->history_days > 0)
			ADD("past_days", hist, NULL);
		if (o->days >= 0)
			ADD("forecast_days", days, NULL);
	}
#undef ADD
	return rc;
}

int cs_request_check(const struct cs_request *o)
{
	int mb = o->provider == CS_PROVIDER_METEOBLUE;
	if (!(o->lat_deg >= -90.0 && o->lat_deg <= 90.0) ||
	    !(o->lon_deg >= -180.0 && o->lon_deg <= 180.0))
		return cs_error(CS_EINVAL, "latitude must lie in -90..90 and longitude "
				"in -180..180 degrees");
	int dmin = mb ? 1 : 0, dmax = mb ? 7 : 16, hmax = mb ? 4 : 92;
	if (o->days != -1 && (o->days < dmin || o->days > dmax))
		return cs_error(CS_EINVAL, "--days: %d is out of range %d..%d for %s",
				o->days, dmin, dmax, cs_mbfetch_provider_name(o->provider));
	if (o->history_days < 0 || o->history_days > hmax)
		return cs_error(CS_EINVAL, "--history-days: %d is out of range 0..%d "
				"for %s", o->history_days, hmax,
				cs_mbfetch_provider_name(o->provider));
	if (o->days == 0 && o->history_days == 0)
		return cs_error(CS_EINVAL, "--days 0 needs --history-days: nothing to fetch");
	if (o->base_url)
		return check_base(o->base_url);
	return CS_OK;
}
