/* provider.h - hourly weather from the providers: meteoblue's Packages API
 * (basic-1h + clouds-1h, solar-1h) and Open-Meteo's forecast API.  Detection,
 * validation (what mbfetch --check reports) and parsing into UTC series
 * (what wxinterp interpolates).  Facts about both formats:
 * ../shared/WEATHER-APIS.md. */
#ifndef CS_PROVIDER_H
#define CS_PROVIDER_H

#include <stddef.h>

enum cs_provider { CS_PROVIDER_METEOBLUE, CS_PROVIDER_OPENMETEO };

/* The variables cloudscape uses, in SI-like units after parsing. */
enum cs_wxvar {
	CS_VAR_CLOUD_TOTAL,     /* %, 0..100 */
	CS_VAR_CLOUD_LOW,       /* % */
	CS_VAR_CLOUD_MID,       /* % */
	CS_VAR_CLOUD_HIGH,      /* % */
	CS_VAR_PRECIP,          /* mm/h (per hour) */
	CS_VAR_CONV_PRECIP,     /* mm/h; meteoblue convective_precipitation,
				   Open-Meteo showers */
	CS_VAR_WIND_SPEED,      /* m/s (converted from the file's unit) */
	CS_VAR_WIND_FROM,       /* degrees, direction the wind blows from */
	CS_VAR_VISIBILITY,      /* m */
	CS_VAR_FOG_PROBABILITY, /* %, 0..100; meteoblue only */
	CS_VAR_HUMIDITY,        /* relative humidity, % */
	CS_VAR_TEMPERATURE,     /* deg C */
	CS_VAR_IS_DAY,          /* 0 or 1 */
	CS_VAR_SNOW_FRACTION,   /* 0..1 of the precipitation; meteoblue
				   snowfraction */
	CS_VAR_SNOWFALL,        /* cm of snow in the preceding hour;
				   Open-Meteo snowfall */
	CS_VAR_GHI,             /* W/m2, global horizontal, at the hour
				   (meteoblue ghi_instant, Open-Meteo
				   shortwave_radiation_instant) */
	CS_VAR_DNI,             /* W/m2, direct normal, at the hour
				   (dni_instant, direct_normal_irradiance_instant) */
	CS_VAR_DHI,             /* W/m2, diffuse horizontal, at the hour
				   (dif_instant, diffuse_radiation_instant) */
	CS_VAR_COUNT
};

/* Parsed hourly series.  v[k] is NULL when the file lacks variable k;
 * otherwise n values, NaN where the file had null (missing, never 0).
 * Wall-clock times ("YYYY-MM-DD hh:mm", "YYYY-MM-DDThh:mm") are converted
 * to UTC by subtracting the file's offset; integer times (Open-Meteo
 * timeformat=unixtime, meteoblue timestamp_utc) are already UTC. */
struct cs_series {
	enum cs_provider provider;
	char name[64];           /* metadata.name (meteoblue), else "" */
	double lat_deg, lon_deg, alt_m;
	double utc_offset_s;     /* the offset the file reports for its times */
	int n;
	double *time_utc;        /* n, seconds since 1970, strictly increasing by 3600 */
	double *v[CS_VAR_COUNT];
	char key[CS_VAR_COUNT][48]; /* where v[k] came from, for messages:
				       "data_1h.lowclouds", "hourly.showers" */
	char note[160];          /* what parsing left out and why, or "" */
};

/* A visibility equal at every one of at least this many hours of a file
 * is a model's default: cs_provider_parse drops it (v NULL, note). */
#define CS_CONST_VIS_HOURS 24

/* A short description of a variable: "low cloud cover". */
const char *cs_wxvar_name(enum cs_wxvar k);

/* Up to max problems found in a provider response, each one line naming
 * the field and index ("data_1h.lowclouds[17]: 130 is outside 0..100"). */
struct cs_problems {
	int count;               /* problems found (may exceed the number kept) */
	char msg[32][256];       /* the first 32 */
};

/* Detects the provider of a JSON document from its content; 0 or CS_EDATA. */
int cs_provider_detect(const char *json, size_t len, enum cs_provider *p);

/* Validates a provider response: required objects and arrays present
 * (low/mid/high cloud cover, precipitation, wind speed and direction),
 * every array as long as time, times strictly increasing in 1-hour steps,
 * units cloudscape reads (ms-1/kmh/mph/kn, mm/inch, m/ft, C/F are
 * converted by cs_provider_parse; bft, 2char and unknown units are
 * problems), values in range; nulls are allowed.  Recognises provider
 * error bodies ({"error":true,"reason":...}, {"error_message":...}; their
 * text verbatim, unredacted), HTML pages (their title), truncated and
 * malformed JSON and empty input.  Returns 0 when there is no problem,
 * else CS_EDATA with the problems in *pr (and the first as cs_errmsg()). */
int cs_provider_check(const char *json, size_t len, struct cs_problems *pr);

/* Parses (after validating) into series; name (the file's, usually) starts
 * the error message: "site.json: data_1h.time[5]: ... (and 3 more
 * problems)".  On error *s is empty (safe to free). */
int cs_provider_parse(const char *json, size_t len, const char *name,
		      struct cs_series *s);
void cs_series_free(struct cs_series *s);

#endif
