/* What a frame says it shows: the description written into its PNG text
 * and EXR attributes, and the caption stamped on it (--caption). */
#include "apps/cloudrender_run.h"

#include "core/err.h"
#include "core/fmt.h"
#include "core/time.h"
#include "render/scene.h"
#include "weather/viewfile.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifndef CS_VERSION
#define CS_VERSION "unknown"
#endif

#define N(v, d) cs_num_round((v), (d)).s

static void put_string(FILE *f, const char *s)
{
	fputc('"', f);
	for (const unsigned char *c = (const unsigned char *)s; *c; c++)
		if (*c == '"' || *c == '\\')
			fprintf(f, "\\%c", *c);
		else if (*c < 0x20)
			fprintf(f, "\\u%04x", *c);
		else
			fputc(*c, f);
	fputc('"', f);
}

static void put_quality(FILE *f, const struct cs_cloudrender_opts *o,
			const struct cs_cloudrender_result *r)
{
	static const char *const march[] = {"standard", "naive", "skip", "adaptive"};
	static const char *const light[] = {"uniform", "quadratic", "geometric", "cone", "cache", "auto"};
	const struct cs_render_settings *s = &r->settings;
	fputs(",\"quality\":{\"preset\":", f);
	put_string(f, o->quality ? o->quality : "");
	fprintf(f, ",\"integrator\":\"%s\"", o->reference ? "reference" : "march");
	if (o->reference)
		fprintf(f, ",\"spp\":%d,\"max_bounces\":%d", o->spp, o->max_bounces);
	fprintf(f, ",\"steps\":%d,\"max_steps\":%d,\"light_steps\":%d,\"ms_octaves\":%d,"
		"\"haze_steps\":%d,\"min_transmittance\":%s,\"march\":\"%s\","
		"\"light_march\":\"%s\",\"source_every\":%d,\"tower_cell_m\":%s,\"heap_towers\":%s,\"deck_lattice\":\"%s\",\"ground_sky\":\"%s\","
		"\"ambient\":%s,\"jitter\":%s,"
		"\"seed\":%u,\"haze\":%s},\"exposure_ev\":%s", s->steps, s->max_steps,
		s->light_steps, s->ms_octaves, s->haze_steps, N(s->min_transmittance, 6),
		(unsigned)s->march < sizeof march / sizeof march[0] ? march[s->march] : "?",
		(unsigned)s->light_march < sizeof light / sizeof light[0] ? light[s->light_march]
									: "?",
		s->source_every > 1 ? s->source_every : 1, N(s->tower_cell_m, 1),
		s->heap_towers ? "true" : "false",
		s->deck_lattice == CS_DECK_EXCHANGE	 ? "exchange"
		: s->deck_lattice == CS_DECK_DIFFUSION ? "diffusion"
							: "off",
		s->ground_sky == CS_GROUND_SKY_FIELD	? "field"
		: s->ground_sky == CS_GROUND_SKY_DOME ? "dome"
						      : "columns",
		s->ambient ? "true" : "false", N(s->jitter, 3),
		(unsigned)s->seed,
		o->no_haze ? "false" : "true", N(r->exposure_ev, 3));
}

static void put_weather(FILE *f, const struct cs_wx *wx)
{
	fputs(",\"weather\":{\"site\":{\"name\":", f);
	put_string(f, wx->site.name);
	fprintf(f, ",\"lat_deg\":%s,\"lon_deg\":%s,\"alt_m\":%s},\"layers\":[",
		N(wx->site.lat_deg, 6), N(wx->site.lon_deg, 6), N(wx->site.alt_m, 0));
	for (int i = 0; i < wx->nlayers; i++)
		fprintf(f, "%s{\"genus\":\"%s\",\"coverage\":%s,\"base_m\":%s,\"top_m\":%s}",
			i ? "," : "", cs_genus_name(wx->layers[i].genus),
			N(wx->layers[i].coverage, 3), N(wx->layers[i].base_m, 0),
			N(wx->layers[i].top_m, 0));
	fprintf(f, "],\"precipitation_mm_h\":%s,\"snow_fraction\":%s,"
		"\"wind\":{\"speed_m_s\":%s,\"from_deg\":%s},\"visibility_m\":%s,"
		"\"fog_probability\":%s", N(wx->precipitation_mm_h, 3),
		N(wx->snow_fraction, 3), N(wx->wind_speed_m_s, 2), N(wx->wind_from_deg, 1),
		N(wx->visibility_m, 0), N(wx->fog_probability, 3));
	if (!isnan(wx->temperature_c))
		fprintf(f, ",\"temperature_c\":%s", N(wx->temperature_c, 2));
	if (wx->drift.known) { /* where the clouds were carried: the frame again */
		char since[32];
		cs_time_format(wx->drift.since_utc, since, sizeof since);
		fprintf(f, ",\"drift\":{\"since_utc\":\"%s\",\"east_m\":%s,", since,
			N(wx->drift.east_m, 2));
		fprintf(f, "\"north_m\":%s,\"axis_deg\":%s}", N(wx->drift.north_m, 2),
			N(wx->drift.axis_deg, 3));
	}
	fprintf(f, ",\"far_sites\":%d}", wx->nfar);
}

int cs_cloudrender_meta_json(const struct cs_cloudrender_opts *o,
			     const struct cs_cloudrender_result *r, char **json)
{
	static const char *const proj[] = {"perspective", "fisheye", "equirect"};
	char *buf = NULL, when[32];
	size_t size;
	*json = NULL;
	FILE *f = open_memstream(&buf, &size);
	if (f == NULL)
		return cs_error(CS_ENOMEM, "out of memory describing the frame");
	cs_time_format(r->wx.time_utc, when, sizeof when);
	fprintf(f, "{\"program\":\"cloudrender\",\"version\":\"%s\",\"time_utc\":\"%s\","
		"\"size\":[%d,%d],\"camera\":{\"lat_deg\":%s,\"lon_deg\":%s,\"alt_m\":%s,"
		"\"azimuth_deg\":%s,\"elevation_deg\":%s,\"fov_deg\":%s,\"projection\":\"%s\"",
		CS_VERSION, when, o->width, o->height, N(r->cam_lat_deg, 6),
		N(r->cam_lon_deg, 6), N(r->cam_alt_m, 1), N(r->look_az_deg, 3),
		N(r->look_el_deg, 3), N(r->fov_deg, 3),
		(unsigned)o->projection < 3 ? proj[o->projection] : "?");
	if (o->view) { /* the view's own name, however --view spelt it */
		const struct cs_view *v = cs_viewset_find(o->views, o->view);
		fputs(",\"view\":", f);
		put_string(f, v ? v->name : o->view);
	}
	fprintf(f, "},\"sun\":{\"azimuth_deg\":%s,\"elevation_deg\":%s}",
		N(r->sun_azimuth_deg, 3), N(r->sun_elevation_deg, 3));
	put_quality(f, o, r);
	if (o->noise_path) { /* the noise the clouds are made of */
		fputs(",\"noise\":{\"file\":", f);
		put_string(f, strcmp(o->noise_path, "-") == 0 ? "standard input" : o->noise_path);
	} else {
		fprintf(f, ",\"noise\":{\"baked_size\":%d", o->noise_size);
	}
	fputc('}', f);
	put_weather(f, &r->wx);
	fputc('}', f);
	int bad = ferror(f);
	if (fclose(f) != 0 || bad) {
		free(buf);
		return cs_error(CS_ENOMEM, "out of memory describing the frame");
	}
	*json = buf;
	return CS_OK;
}

/* "30 km", "800 m" */
static void distance_text(char *buf, size_t size, double m)
{
	if (m >= 10000.0)
		snprintf(buf, size, "%.0f km", m / 1000.0);
	else if (m >= 1000.0)
		snprintf(buf, size, "%.1f km", m / 1000.0);
	else
		snprintf(buf, size, "%.0f m", m);
}

void cs_cloudrender_caption_text(const struct cs_cloudrender_result *r, char *buf,
				 size_t size)
{
	const struct cs_wx *wx = &r->wx;
	char when[32];
	size_t k = 0;
#define ADD(...) (k += (size_t)snprintf(buf + k, k < size ? size - k : 0, __VA_ARGS__))
	cs_time_format(wx->time_utc, when, sizeof when);
	/* "2021-06-14T16:45:00Z" as "2021-06-14 16:45 UTC" */
	ADD("%.10s %.5s UTC", when, when + 11);
	if (wx->site.name[0])
		ADD("  %s", wx->site.name);
	ADD("  sun %.0f deg\n", r->sun_elevation_deg);
	if (wx->nlayers == 0)
		ADD("clear sky");
	for (int i = 0; i < wx->nlayers; i++)
		ADD("%s%s %.0f%% %.0f-%.0f m", i ? ", " : "", cs_genus_name(wx->layers[i].genus),
		    wx->layers[i].coverage * 100.0, wx->layers[i].base_m, wx->layers[i].top_m);
	char vis[32];
	distance_text(vis, sizeof vis, wx->visibility_m);
	if (wx->precipitation_mm_h > 0.0)
		ADD("\n%s %.*f mm/h, ", wx->snow_fraction > 0.5 ? "snow" : "rain",
		    wx->precipitation_mm_h < 0.1 ? 2 : 1, wx->precipitation_mm_h);
	else
		ADD("\ndry, ");
	ADD("wind %.1f m/s from %.0f deg, visibility %s", wx->wind_speed_m_s,
	    wx->wind_from_deg, vis);
	if (wx->fog_probability > 0.0)
		ADD(", fog %.0f%%", wx->fog_probability * 100.0);
	if (!isnan(wx->temperature_c))
		ADD(", %.1f C", wx->temperature_c);
#undef ADD
	if (size > 0 && k >= size)
		buf[size - 1] = '\0';
}
