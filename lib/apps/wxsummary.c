/* wxinterp --summary (wxsummary.h). */
#include "apps/wxsummary.h"

#include "core/err.h"
#include "core/fmt.h"
#include "core/time.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

const char *cs_genus_abbrev(enum cs_genus g)
{
	static const char *const ab[CS_GENUS_COUNT] = {
		"Ci", "Cc", "Cs", "Ac", "As", "Ns", "Sc", "St", "Cu", "Cb"};
	return (int)g >= 0 && g < CS_GENUS_COUNT ? ab[g] : "?";
}

double cs_wxsum_cover(const struct cs_wxsum_row *r)
{
	if (r->ob.observed.has_cloud_cover)
		return r->ob.observed.total_cloud_cover;
	return 1.0 - (1.0 - r->ob.low) * (1.0 - r->ob.mid) * (1.0 - r->ob.high);
}

/* A growing text; out of memory is remembered and reported at the end. */
struct text {
	char *s;
	size_t len, cap;
	int failed;
};

static void put(struct text *t, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

static void put(struct text *t, const char *fmt, ...)
{
	va_list ap;
	va_start(ap, fmt);
	int n = vsnprintf(NULL, 0, fmt, ap);
	va_end(ap);
	if (t->failed || n < 0) {
		t->failed = 1;
		return;
	}
	if (t->len + (size_t)n + 1 > t->cap) {
		size_t cap = t->cap * 2 + (size_t)n + 256;
		char *s = realloc(t->s, cap);
		if (s == NULL) {
			t->failed = 1;
			return;
		}
		t->s = s;
		t->cap = cap;
	}
	va_start(ap, fmt);
	vsnprintf(t->s + t->len, t->cap - t->len, fmt, ap);
	va_end(ap);
	t->len += (size_t)n;
}

/* Writes and empties the text. */
static int flush(struct text *t, struct cs_outfile *of)
{
	if (t->failed)
		return cs_error(CS_ENOMEM, "out of memory");
	int rc = t->len ? cs_outfile_write(of, t->s, t->len) : CS_OK;
	t->len = 0;
	return rc;
}

/* mm/h with at most two decimals, no trailing zeros: "0", "0.6", "0.25". */
static const char *amount(char *buf, size_t size, double v)
{
	snprintf(buf, size, "%.2f", v);
	char *e = buf + strlen(buf);
	while (e > buf && e[-1] == '0')
		*--e = '\0';
	if (e > buf && e[-1] == '.')
		*--e = '\0';
	if (strcmp(buf, "-0") == 0)
		strcpy(buf, "0");
	return buf;
}

/* "2024-10-07 19:00" of a UTC time. */
static void hour_text(double t, char *buf, size_t size)
{
	const char *iso = cs_time_text(t).s; /* 2024-10-07T19:00:00Z */
	snprintf(buf, size, "%.10s %.5s", iso, iso + 11);
}

static void hourly_text(struct text *t, const struct cs_wxsum_row *r)
{
	const struct cs_wx *w = &r->wx;
	char when[32], rain[32], snow[32];
	hour_text(w->time_utc, when, sizeof when);
	double sun = r->ob.sun_elevation_deg;
	amount(rain, sizeof rain, w->precipitation_mm_h);
	if (w->precipitation_mm_h > 0)
		snprintf(snow, sizeof snow, "%.0f%%", 100 * w->snow_fraction);
	else
		snprintf(snow, sizeof snow, "-");
	put(t, "%s  %-4s %+4.0f  %4.0f%% %4.0f%% %4.0f%% %4.0f%%  %6s  %4s  %6.0f  %3.0f%%  ",
	    when, isnan(sun) ? "?" : sun > 0 ? "up" : "down", sun,
	    100 * cs_wxsum_cover(r), 100 * r->ob.low, 100 * r->ob.mid, 100 * r->ob.high,
	    rain, snow, w->visibility_m, 100 * w->fog_probability);
	if (w->nlayers == 0)
		put(t, "clear");
	for (int i = 0; i < w->nlayers; i++) {
		const struct cs_wx_layer *l = &w->layers[i];
		put(t, "%s%s %.0f%% %.0f-%.0f m", i ? ", " : "", cs_genus_abbrev(l->genus),
		    100 * l->coverage, l->base_m, l->top_m);
	}
	put(t, "\n");
}

static void hourly_json(struct text *t, const struct cs_wxsum_row *r)
{
	const struct cs_wx *w = &r->wx;
	put(t, "{\"time_utc\":\"%s\",\"sun_elevation_deg\":%.1f,\"sun_up\":%s,"
	    "\"cloud_cover\":%s,", cs_time_text(w->time_utc).s, r->ob.sun_elevation_deg,
	    r->ob.sun_elevation_deg > 0 ? "true" : "false", cs_num(cs_wxsum_cover(r)).s);
	put(t, "\"cover_low\":%s,", cs_num(r->ob.low).s);
	put(t, "\"cover_mid\":%s,", cs_num(r->ob.mid).s);
	put(t, "\"cover_high\":%s,\"layers\":[", cs_num(r->ob.high).s);
	for (int i = 0; i < w->nlayers; i++) {
		const struct cs_wx_layer *l = &w->layers[i];
		put(t, "%s{\"genus\":\"%s\",\"coverage\":%s,\"base_m\":%.0f,\"top_m\":%.0f}",
		    i ? "," : "", cs_genus_name(l->genus), cs_num(l->coverage).s, l->base_m,
		    l->top_m);
	}
	put(t, "],\"precipitation_mm_h\":%s,", cs_num(w->precipitation_mm_h).s);
	put(t, "\"snow_fraction\":%s,", cs_num(w->snow_fraction).s);
	put(t, "\"visibility_m\":%s,", cs_num(w->visibility_m).s);
	put(t, "\"fog_probability\":%s}\n", cs_num(w->fog_probability).s);
}

/* One UTC day's figures. */
struct day {
	char date[16];
	int hours, sun_hours, rain_hours;
	double cover_sum, cover_max, rain_mm, rain_max, snow_mm, vis_min, fog_max;
	int genus_hours[CS_GENUS_COUNT];
};

static void day_add(struct day *d, const struct cs_wxsum_row *r, double step_h)
{
	const struct cs_wx *w = &r->wx;
	double c = cs_wxsum_cover(r);
	d->hours++;
	d->sun_hours += r->ob.sun_elevation_deg > 0;
	d->rain_hours += w->precipitation_mm_h > 0;
	d->cover_sum += c;
	d->cover_max = fmax(d->cover_max, c);
	d->rain_mm += w->precipitation_mm_h * step_h;
	d->snow_mm += w->precipitation_mm_h * w->snow_fraction * step_h;
	d->rain_max = fmax(d->rain_max, w->precipitation_mm_h);
	d->vis_min = fmin(d->vis_min, w->visibility_m);
	d->fog_max = fmax(d->fog_max, w->fog_probability);
	int seen[CS_GENUS_COUNT] = {0};
	for (int i = 0; i < w->nlayers; i++)
		if (!seen[w->layers[i].genus]++)
			d->genus_hours[w->layers[i].genus]++;
}

static void day_text(struct text *t, const struct day *d)
{
	char rain[32], rmax[32], snow[32];
	put(t, "%s  %5d  %6d  %4.0f%% %4.0f%%  %7s  %6d  %7s  %7s  %6.0f  %3.0f%%  ", d->date,
	    d->hours, d->sun_hours, 100 * d->cover_sum / d->hours, 100 * d->cover_max,
	    amount(rain, sizeof rain, d->rain_mm), d->rain_hours,
	    amount(rmax, sizeof rmax, d->rain_max), amount(snow, sizeof snow, d->snow_mm),
	    d->vis_min, 100 * d->fog_max);
	int any = 0;
	for (int g = 0; g < CS_GENUS_COUNT; g++)
		if (d->genus_hours[g]) {
			put(t, "%s%s %d", any ? ", " : "", cs_genus_abbrev((enum cs_genus)g),
			    d->genus_hours[g]);
			any = 1;
		}
	put(t, "%s\n", any ? "" : "clear");
}

static void day_json(struct text *t, const struct day *d)
{
	put(t, "{\"date_utc\":\"%s\",\"hours\":%d,\"sun_up_hours\":%d,\"cloud_cover_mean\":%.3f,"
	    "\"cloud_cover_max\":%s,\"precipitation_mm\":%s,\"rain_hours\":%d,",
	    d->date, d->hours, d->sun_hours, d->cover_sum / d->hours, cs_num(d->cover_max).s,
	    cs_num(round(d->rain_mm * 1e6) / 1e6).s, d->rain_hours);
	put(t, "\"precipitation_max_mm_h\":%s,", cs_num(d->rain_max).s);
	put(t, "\"snow_mm\":%s,", cs_num(round(d->snow_mm * 1e6) / 1e6).s);
	put(t, "\"visibility_min_m\":%s,", cs_num(d->vis_min).s);
	put(t, "\"fog_probability_max\":%s,\"genus_hours\":{", cs_num(d->fog_max).s);
	int any = 0;
	for (int g = 0; g < CS_GENUS_COUNT; g++)
		if (d->genus_hours[g]) {
			put(t, "%s\"%s\":%d", any ? "," : "", cs_genus_name((enum cs_genus)g),
			    d->genus_hours[g]);
			any = 1;
		}
	put(t, "}}\n");
}

static void header(struct text *t, const struct cs_wxsum_row *r, int daily)
{
	const struct cs_wx_site *s = &r->wx.site;
	put(t, "# %s%s%.4f, %.4f, %.0f m; times UTC; rain in mm (per hour); visibility "
	    "in m; cover: the provider's total, then low/mid/high\n", s->name,
	    s->name[0] ? ": " : "", s->lat_deg, s->lon_deg, s->alt_m);
	if (daily)
		put(t, "%-10s  %5s  %6s  %5s %5s  %7s  %6s  %7s  %7s  %6s  %4s  %s\n",
		    "# day", "hours", "sun up", "cover", "max", "rain", "rain h", "max/h",
		    "snow", "vis", "fog", "genera (hours)");
	else
		put(t, "%-16s  %-4s %4s  %5s %5s %5s %5s  %6s  %4s  %6s  %4s  %s\n",
		    "# time (UTC)", "sun", "deg", "cover", "low", "mid", "high", "rain",
		    "snow", "vis", "fog", "layers (genus cover base-top m above sea level)");
}

int cs_wxsum_write(const struct cs_wxsum_row *rows, long n, double step_s,
		   int daily, int json, struct cs_outfile *of)
{
	struct text t = {0};
	int rc = CS_OK;
	if (n > 0 && !json)
		header(&t, &rows[0], daily);
	struct day d;
	int open = 0;
	for (long i = 0; rc == CS_OK && i < n; i++) {
		if (!daily) {
			(json ? hourly_json : hourly_text)(&t, &rows[i]);
		} else {
			char date[16];
			snprintf(date, sizeof date, "%.10s", cs_time_text(rows[i].wx.time_utc).s);
			if (open && strcmp(date, d.date) != 0) {
				(json ? day_json : day_text)(&t, &d);
				open = 0;
			}
			if (!open) {
				memset(&d, 0, sizeof d);
				snprintf(d.date, sizeof d.date, "%s", date);
				d.vis_min = INFINITY;
				open = 1;
			}
			day_add(&d, &rows[i], step_s / 3600);
		}
		if (t.len > 65536)
			rc = flush(&t, of);
	}
	if (rc == CS_OK && open)
		(json ? day_json : day_text)(&t, &d);
	if (rc == CS_OK)
		rc = flush(&t, of);
	free(t.s);
	return rc;
}
