/* cloudrender - render a weather state as a physically based cloudscape. */
#include "cli.h"

#include "apps/cloudrender_run.h"
#include "io/skyclass.h"
#include "core/err.h"
#include "render/device.h"
#include "render/scene.h"
#include "core/time.h"

#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <unistd.h>

#ifndef CS_VERSION
#define CS_VERSION "unknown"
#endif

/* ---- series: every state of --wx a frame (cloudrender(1), SERIES) ---- */

static void series_usage(void)
{
	printf("A series: a --wx file of several states (JSON Lines, as wxinterp writes\n"
	       "for a time range) renders every state as a frame, its -o names numbered as\n"
	       "ffmpeg numbers frames: %%d, %%05d (5 digits), %%%% a literal percent; frame\n"
	       "numbers are the state's index from 0 (--start-number).\n"
	       "      --frames A:B       only frames A to B-1, by the numbers in the names\n"
	       "                         (A: to the end, :B from the first, N alone: frame N)\n"
	       "      --start-number N   the first state's frame number (default 0)\n"
	       "      --skip-existing    write no output that exists; a frame whose outputs\n"
	       "                         all exist is not rendered (resume a series)\n"
	       "      --caption          stamp the time and the weather in the lower left\n"
	       "                         corner (every output, EXR too)\n");
}

enum {
	OPT_FRAMES = 512, OPT_START_NUMBER, OPT_SKIP_EXISTING, OPT_CAPTION,
};
#define SERIES_LONGOPTS                                                        \
	{"frames", required_argument, NULL, OPT_FRAMES},                       \
	{"start-number", required_argument, NULL, OPT_START_NUMBER},           \
	{"skip-existing", no_argument, NULL, OPT_SKIP_EXISTING},               \
	{"caption", no_argument, NULL, OPT_CAPTION},

/* --frames A:B, A:, :B or N. */
static void parse_frames(const char *s, struct cs_cloudrender_opts *o)
{
	const long max = 2000000000L;
	const char *colon = strchr(s, ':');
	char a[32];
	if (colon == NULL) {
		o->frames_from = cli_long("--frames", s, 0, max);
		o->frames_to = o->frames_from + 1;
		return;
	}
	if ((size_t)(colon - s) >= sizeof a)
		cli_usage_error("--frames: expected A:B, not '%s'", s);
	memcpy(a, s, (size_t)(colon - s));
	a[colon - s] = '\0';
	o->frames_from = a[0] ? cli_long("--frames", a, 0, max) : -1;
	o->frames_to = colon[1] ? cli_long("--frames", colon + 1, 0, max) : -1;
	if (o->frames_from >= 0 && o->frames_to >= 0 && o->frames_to <= o->frames_from)
		cli_usage_error("--frames %s: no frame (B is the first frame not rendered: "
				"%s:%lld renders frame %s)", s, a, o->frames_from + 1, a);
}

/* 1 when opt is a series option (then handled). */
static int series_option(int opt, const char *arg, struct cs_cloudrender_opts *o)
{
	switch (opt) {
	case OPT_FRAMES: parse_frames(arg, o); return 1;
	case OPT_START_NUMBER:
		o->start_number = cli_long("--start-number", arg, 0, 2000000000L);
		return 1;
	case OPT_SKIP_EXISTING: o->skip_existing = 1; return 1;
	case OPT_CAPTION: o->caption = 1; return 1;
	}
	return 0;
}

/* What the frames of a run print: the progress label, -v, --stats. */
struct series_report {
	const struct cs_cloudrender_opts *o;
	int stats;
	char label[64];
	int rendered, skipped;
	double first_s, last_s; /* the first frame's start, the last one's end */
};

static void print_stats(const struct cs_cloudrender_opts *o,
			const struct cs_cloudrender_result *r);

static void frame_report(void *user, const struct cs_cloudrender_frame *f,
			 const struct cs_cloudrender_result *r)
{
	struct series_report *rep = user;
	int series = f->states > 1 || f->count > 1;
	switch (f->stage) {
	case CS_FRAME_START:
		if (rep->first_s < 0.0)
			rep->first_s = cli_mono_s();
		if (series)
			snprintf(rep->label, sizeof rep->label, "frame %d/%d", f->nth, f->count);
		break;
	case CS_FRAME_SKIPPED:
		rep->skipped++;
		if (cli_verbose) {
			cli_progress_break();
			cli_err("frame %lld: skipped, its outputs exist", f->number);
		}
		break;
	case CS_FRAME_DONE:
		rep->rendered++;
		rep->last_s = cli_mono_s(); /* (frames written while others render: not a sum) */
		if (cli_verbose && series) {
			cli_progress_break();
			cli_err("frame %lld (%d/%d, state %d of %d): %s%s in %.2f s", f->number,
				f->nth, f->count, f->index + 1, f->states, f->outputs[0],
				f->noutputs > 1 ? " ..." : "", f->wall_s);
		}
		if (rep->stats) {
			cli_progress_break();
			print_stats(rep->o, r);
		}
		break;
	}
}

static void usage(void)
{
	printf("Usage: cloudrender [options] -o FILE.png|.exr|.tif|.jpg [-o FILE...]\n"
	       "Render the sky of a weather state: sun and sky for the date and place,\n"
	       "volumetric clouds of every genus, flat ground, haze and rain.\n"
	       "\n"
	       "  -o, --output FILE      the format by the extension: .png: 8-bit sRGB, tone\n"
	       "                         mapped; .exr: linear half RGBA (A = 1 - cloud\n"
	       "                         transmittance) + float Z (metres); .tif/.tiff:\n"
	       "                         16-bit sRGB, tone mapped; .jpg/.jpeg: 8-bit sRGB;\n"
	       "                         '-' = PNG on standard output; repeat for several\n"
	       "                         (written all together or none of them)\n"
	       "  -of, --output-format F the format of the -o outputs after it, whatever\n"
	       "                         their names: PNG, EXR, GTiff (TIFF) or JPEG (JPG)\n"
	       "      --png16            PNG with 16 bits a sample (sRGB, tone mapped)\n"
	       "      --float            EXR: 32-bit float RGBA instead of half; TIFF: 32-bit\n"
	       "                         float linear R, G, B, A, Z bands (as the EXR's)\n"
	       "      --jpeg-quality N   JPEG quality, 1..100 (default 90)\n"
	       "      --no-clobber       never replace an existing file (default: replace\n"
	       "                         it, whole, once the run has succeeded)\n"
	       "      --wx FILE          weather state, cloudwx JSON ('-' = standard input;\n"
	       "                         default: built-in fair weather over Bern)\n"
	       "      --noise FILE       noise volume from noisebake (default: baked in memory)\n"
	       "      --noise-size N     size of the in-memory noise, 16..256 (default 64);\n"
	       "                         kept in $XDG_CACHE_HOME/cloudscape (or\n"
	       "                         ~/.cache/cloudscape) for the next run;\n"
	       "                         CLOUDSCAPE_NO_CACHE=1 bakes it every time\n"
	       "      --terrain FILE     heightfield from terrainprep (EXR + .json sidecar;\n"
	       "                         default: flat ground at the weather site's height)\n"
	       "      --terrain-color FILE  PNG draped over the terrain's grid\n"
	       "      --terrain-cpt FILE    colour the terrain by height with a GMT CPT palette\n"
	       "                         (z0 r g b z1 r g b lines, as makecpt writes)\n"
	       "      --time TIME        UTC time, ISO 8601, or 'now' (default: the weather\n"
	       "                         state's)\n"
	       "      --view NAME        named viewpoint, any case: gurten, bantiger, or\n"
	       "                         one of the --views file\n"
	       "      --views FILE       more named viewpoints, one a line: NAME LAT LON\n"
	       "                         ALT_M AZ EL FOV [DESCRIPTION] (default:\n"
	       "                         $XDG_CONFIG_HOME/cloudscape/views if it exists)\n"
	       "      --list-views       list the viewpoints and exit\n"
	       "      --camera LAT,LON,ALT_M  camera position (degrees, metres above sea level;\n"
	       "                         LAT,LON with --camera-agl)\n"
	       "      --camera-agl M     the camera M metres above the terrain (or, without\n"
	       "                         terrain, the weather site's ground), 0..100000\n"
	       "      --look AZ,EL       view azimuth (from north, clockwise) and elevation, degrees\n"
	       "      --look-at LAT,LON,ALT_M  look at this point (degrees, metres above sea\n"
	       "                         level) instead of --look\n"
	       "      --fov DEG          horizontal field of view, 1..179 (default 70, views 60)\n"
	       "      --projection P     perspective (default); fisheye: an all-sky camera\n"
	       "                         looking up (north up, east left); equirect: a\n"
	       "                         360x180 environment map around the look azimuth\n"
	       "      --size WxH         image size in pixels (default 640x360)\n"
	       "      --quality NAME     low, medium (default), high or reference\n"
	       "      --steps N          view samples across a layer's thickness, 1..100000\n"
	       "      --light-steps N    samples toward the sun, 1..10000\n"
	       "      --ms-octaves N     multiple-scattering octaves, 1 (single scattering)..4\n"
	       "                         (not in the first two layers of 70 %% cover\n"
	       "                         and more or thin for the sun's beam, nor in\n"
	       "                         cumulonimbus of 20 %% cover and less: their\n"
	       "                         light fields hold it)\n"
	       "      --max-steps N      most view samples in one crossing of a layer,\n"
	       "                         1..1000000 (at least --steps; longer crossings\n"
	       "                         grow their steps along the ray)\n"
	       "      --min-transmittance X  a ray stops when it sees less than X, 0..0.5\n"
	       "      --march M          standard (default); naive: a plain constant-step\n"
	       "                         sum, the baseline; skip: empty space probed every\n"
	       "                         4 steps and skipped; adaptive: a step deeper than\n"
	       "                         0.5 in optical depth marched again in up to 4 parts\n"
	       "      --light-march M    auto (low, medium, high): cache where the frame\n"
	       "                         has a pixel for every 32 of a layer's cells, else\n"
	       "                         geometric; cache: the depth toward the sun\n"
	       "                         looked up in a volume built once a frame, geometric\n"
	       "                         where a layer has none; geometric (reference):\n"
	       "                         steps toward the sun growing from the point;\n"
	       "                         uniform: equal steps; quadratic: samples at\n"
	       "                         (k + 1/2)^2 / n^2 of the path; cone: the geometric\n"
	       "                         steps spread sideways by up to 0.2 of their distance\n"
	       "      --source-every N   2 (low, medium, high): a cloudy sample's light at\n"
	       "                         every other view sample, the one between taking\n"
	       "                         the mean of its neighbours' (the density still\n"
	       "                         at each); 1 (reference, and with --device cuda\n"
	       "                         low, medium and high, whose light is cached): at\n"
	       "                         every one\n"
	       "      --tower-cell M     the towers of cumulonimbus (and the heaps of\n"
	       "                         cumulus with --heap-towers on), and the decks\n"
	       "                         of more than half cover: the spacing of the\n"
	       "                         lattice their diffused light is solved on,\n"
	       "                         m, 50..5000 (the presets 400; coarsened to keep\n"
	       "                         the lattice within 2e7 nodes); 0: none, the\n"
	       "                         march's model and the decks' columns alone\n"
	       "      --deck-lattice M   a thick deck (more than half cover, lit by light\n"
	       "                         fields): diffusion (low, medium): takes the\n"
	       "                         light diffusing between its columns from\n"
	       "                         --tower-cell's lattice, its faces toward the\n"
	       "                         gaps lit by the sky and the ground; exchange\n"
	       "                         (high, reference; on is the same): those faces\n"
	       "                         take what their rays gather from the cloud\n"
	       "                         across the gaps; off: its columns alone\n"
	       "      --heap-towers B    on: the heaps of cumulus lit as towers (their\n"
	       "                         tilted columns and diffused light, with\n"
	       "                         --tower-cell's lattice; high and reference);\n"
	       "                         off: as the columns of a slab (low, medium)\n"
	       "      --ground-sky M     the diffuse light on the ground under clouds:\n"
	       "                         field (high, reference): the sky the frame draws\n"
	       "                         traced from 64 x 64 points over 24 km around the\n"
	       "                         camera, most rays where the frame sees ground;\n"
	       "                         dome: their mean, from 32 x 32 points, 4 rays\n"
	       "                         each; columns (low, medium): the area mean of\n"
	       "                         the clouds' slab columns, but the field where\n"
	       "                         rain or snow falls under them without fog (it\n"
	       "                         takes its light)\n"
	       "      --haze-steps N     samples of the clouds' shadows in the haze over\n"
	       "                         the first 20 km (crepuscular rays), 0..10000;\n"
	       "                         0: their area mean only\n"
	       "      --integrator I     march (default): the fast ray march the quality\n"
	       "                         settings tune; reference: an unbiased Monte Carlo\n"
	       "                         path tracer (full multiple scattering, no haze)\n"
	       "      --spp N            reference: paths per pixel, 1..1000000 (default 64)\n"
	       "      --max-bounces N    reference: scattering events per path, 0 (no\n"
	       "                         limit, the default)..1000000; 1: single scattering\n"
	       "      --cloud-depth D    forecast (default): where the weather state has the\n"
	       "                         forecast's radiation (cloudwx \"observed\"), the sun\n"
	       "                         8 deg up or more (fully from 12), no fog and no far\n"
	       "                         sites, the sheets' depth\n"
	       "                         (cirrus, cirrocumulus, cirrostratus, altostratus,\n"
	       "                         nimbostratus, stratus) scaled so that the clouds\n"
	       "                         let through the forecast's DNI (delta-scaled, as a\n"
	       "                         radiation scheme counts it); genus: the genera's\n"
	       "                         typical optical depths\n"
	       "      --sky-level L      preetham (default): the sky's brightness as\n"
	       "                         Preetham's model gives it, 1.2 to 2.7 times the\n"
	       "                         diffuse light of the Ineichen-Perez clear-sky model\n"
	       "                         over the meteoblue capture's hours; ineichen: that\n"
	       "                         model's diffuse irradiance for the visibility's\n"
	       "                         aerosol (Preetham's pattern and colour kept; the\n"
	       "                         sun's beam as before)\n"
	       "      --no-haze          no aerosol haze between the eye and the clouds (fog\n"
	       "                         stays): what the reference integrator compares with\n"	       "      --no-ambient       no sky light on the clouds\n"
	       "      --no-jitter        sample at step midpoints (banding instead of noise)\n"
	       "      --seed N           seed of the per-pixel jitter, 0..4294967295 (default 0)\n"
	       "      --exposure EV|auto PNG exposure in stops, -20..20 (default 0), or auto:\n"
	       "                         from the image's mean luminance (twilight, night)\n"
	       "  -t, --threads N        worker threads, 1..256, also solving the light in\n"
	       "                         fog and cloud decks, compressing an EXR output\n"
	       "                         and, in a series, writing frames while the next\n"
	       "                         ones render (default: all processors)\n"
	       "      --device D         cpu (default): the CPU's threads; cuda: the same\n"
	       "                         integrator on the first CUDA GPU (a build made with\n"
	       "                         make CUDA=1; the march and the reference, not\n"
	       "                         --march adaptive or --light-march cone);\n"
	       "                         where there is none, it says why and exits 1\n"
	       "      --device-bench N   with --device cuda: render the frame N more times\n"
	       "                         on the GPU and print the mean time of one (kernel\n"
	       "                         only, by CUDA events) and frames per second\n"
	       "      --stats            print a JSON summary on standard error, with the\n"
	       "                         ground irradiance (GHI, DNI, DHI in W/m2) at the\n"
	       "                         camera and over 10 km around the site\n"
	       "  -q, --quiet            no progress bar\n"
	       "  -v, --verbose          say what is rendered (time, site, sun, camera,\n"
	       "                         layers, effects, quality), the time of each phase\n"
	       "                         and where it rendered (the CPU's kernel or the GPU)\n"
	       "  -h, --help             this help\n"
	       "      --version          print the version\n"
	       "\n");
	series_usage();
	printf("\n"
	       "Exit status: 0 success, 1 data or runtime error, 2 usage error; stopped\n"
	       "by SIGINT (Ctrl-C), SIGTERM or SIGHUP it finishes the file it is writing,\n"
	       "starts no other, and dies of the signal (130 for SIGINT in the shell).\n"
	       "See cloudrender(1) and cloudwx(5).\n");
}

static void list_view(const struct cs_view *v)
{
	printf("%-10s %9.5f %9.5f %6.0f m  look %5.1f,%4.1f deg  fov %2.0f  %s\n",
	       v->name, v->place->lat_deg, v->place->lon_deg, cs_view_alt_m(v),
	       v->azimuth_deg, v->elevation_deg, v->fov_deg, v->description);
}

/* The --views file's viewpoints, then the built-in ones it does not name. */
static void list_views(const struct cs_viewset *set)
{
	int n;
	const struct cs_view *v = cs_views(&n);
	for (int i = 0; set && i < set->n; i++)
		list_view(&set->views[i]);
	for (int i = 0; i < n; i++)
		if (cs_viewset_find(set, v[i].name) == &v[i])
			list_view(&v[i]);
}

static void print_stats(const struct cs_cloudrender_opts *o,
			const struct cs_cloudrender_result *r)
{
	const struct cs_render_stats *s = &r->stats;
	double px = s->pixels ? (double)s->pixels : 1.0;
	double total = r->t_noise_s + r->t_scene_s + r->t_render_s + r->t_write_s;
	char when[32];
	cs_time_format(r->wx.time_utc, when, sizeof when);
	fprintf(stderr,
		"{\"program\":\"cloudrender\",\"time_utc\":\"%s\",\"size\":[%d,%d],"
		"\"quality\":\"%s\",\"steps\":%d,\"light_steps\":%d,\"ms_octaves\":%d,"
		"\"exposure_ev\":%.3f,"
		"\"wall_s\":{\"noise\":%.3f,\"scene\":%.3f,\"render\":%.3f,\"write\":%.3f,"
		"\"total\":%.3f},"
		"\"pixels\":%llu,\"density_samples\":%llu,\"light_samples\":%llu,"
		"\"rays_terminated_early\":%llu,\"layer_crossings\":%llu,\"terrain_cells\":%llu,"
		"\"density_samples_per_pixel\":%.2f,\"density_samples_per_s\":%.0f,"
		"\"integrator\":\"%s\",",
		when, o->width, o->height, o->quality, r->settings.steps,
		r->settings.light_steps, r->settings.ms_octaves, r->exposure_ev, r->t_noise_s,
		r->t_scene_s, r->t_render_s, r->t_write_s, total,
		(unsigned long long)s->pixels, (unsigned long long)s->density_samples,
		(unsigned long long)s->light_samples,
		(unsigned long long)s->rays_terminated_early,
		(unsigned long long)s->layer_crossings, (unsigned long long)s->terrain_cells,
		(double)s->density_samples / px,
		r->t_render_s > 0 ? (double)s->density_samples / r->t_render_s : 0.0,
		o->reference ? "reference" : "march");
	if (o->reference)
		fprintf(stderr, "\"reference\":{\"spp\":%d,\"max_bounces\":%d,"
			"\"relative_standard_error\":{\"median\":%.4f,\"p95\":%.4f}},",
			o->spp, o->max_bounces, r->ref_rse_median, r->ref_rse_p95);
	fprintf(stderr, "\"sun\":{\"azimuth_deg\":%.3f,\"elevation_deg\":%.3f},\"layers\":[",
		r->sun_azimuth_deg, r->sun_elevation_deg);
	const struct cs_scene *sc = r->scene;
	for (int i = 0; sc && i < sc->nlayers; i++)
		fprintf(stderr, "%s{\"genus\":\"%s\",\"coverage\":%.3f,\"base_m\":%.0f,\"top_m\":%.0f}",
			i ? "," : "", cs_genus_name(sc->layers[i].genus),
			sc->layers[i].coverage, sc->layers[i].base_m, sc->layers[i].top_m);
	fprintf(stderr, "],\"cloud_depth_scale\":%.4f,\"sky_level_scale\":%.4f",
		sc ? sc->cloud_depth_scale : 1.0, sc ? sc->sky_level_scale : 1.0);
	fprintf(stderr, ",\"irradiance_w_m2\":{\"camera\":{\"ghi\":%.1f,\"dni\":%.1f,"
		"\"dhi\":%.1f},\"area\":{\"size_km\":%.0f,\"ghi\":%.1f,\"dni\":%.1f,\"dhi\":%.1f},"
		"\"wall_s\":%.3f}",
		r->irr_camera.ghi_w_m2, r->irr_camera.dni_w_m2, r->irr_camera.dhi_w_m2,
		r->area_size_m / 1000.0, r->irr_area.ghi_w_m2, r->irr_area.dni_w_m2,
		r->irr_area.dhi_w_m2, r->t_irradiance_s);
	if (r->cloud_fraction_rb >= 0.0)
		fprintf(stderr, ",\"sky_imager\":{\"cloud_fraction\":%.3f,\"rb_threshold\":%.2f,"
			"\"opaque_fraction\":%.3f}", r->cloud_fraction_rb, CS_SKY_RB_THRESHOLD,
			r->cloud_fraction_alpha);
	fprintf(stderr, ",\"effects\":[");
	int first = 1;
	unsigned fx = sc ? sc->effects : 0;
	for (int b = 0; sc && cs_effect_name(1u << b); b++)
		if (fx & (1u << b)) {
			fprintf(stderr, "%s\"%s\"", first ? "" : ",", cs_effect_name(1u << b));
			first = 0;
		}
	fprintf(stderr, "]}\n");
}

/* -v, before the frame: what is about to be rendered. */
static void describe(void *user, const struct cs_cloudrender_result *r)
{
	const struct cs_cloudrender_opts *o = user;
	const struct cs_wx *wx = &r->wx;
	const struct cs_scene *sc = r->scene;
	char when[32];
	static const char *const proj[] = {"perspective", "fisheye", "equirect"};
	cs_time_format(wx->time_utc, when, sizeof when);
	cli_err("time %s, site %s%s%.4f, %.4f, %.0f m", when, wx->site.name,
		wx->site.name[0] ? " " : "", wx->site.lat_deg, wx->site.lon_deg, wx->site.alt_m);
	cli_err("sun azimuth %.1f deg, elevation %.1f deg (%s)", r->sun_azimuth_deg,
		r->sun_elevation_deg, r->sun_elevation_deg > -0.8 ? "up" : "down");
	cli_err("camera %.5f, %.5f, %.0f m, looking azimuth %.1f deg, elevation %.1f deg, "
		"fov %.0f deg, %s %dx%d (%s)", r->cam_lat_deg, r->cam_lon_deg, r->cam_alt_m,
		r->look_az_deg, r->look_el_deg, r->fov_deg, proj[o->projection], o->width,
		o->height, r->look_why);
	if (sc->nlayers == 0)
		cli_err("layers: none (clear sky)");
	for (int i = 0; i < sc->nlayers; i++) {
		const struct cs_cloud_layer *l = &sc->layers[i];
		char from[80] = "";
		if (l->site >= 0 && l->site < wx->nfar)
			snprintf(from, sizeof from, " (far site %s)", wx->far[l->site].site.name);
		cli_err("layer %d: %s, cover %.2f, base %.0f m, top %.0f m%s", i + 1,
			cs_genus_name(l->genus), l->coverage, l->base_m, l->top_m, from);
	}
	if (sc->nlayers > 0) {
		double k = sc->cloud_depth_scale;
		const char *bound = fabs(k - CS_BEAM_FIT_K_MIN) < 1e-9 * CS_BEAM_FIT_K_MIN
					    ? ", at the bound: the thinnest the fit makes them"
				    : fabs(k - CS_BEAM_FIT_K_MAX) < 1e-9 * CS_BEAM_FIT_K_MAX
					    ? ", at the bound: the thickest the fit makes them"
					    : "";
		if (k != 1.0)
			cli_err("cloud depth: the sheets' %.3g times the genera's, fitted to the "
				"forecast's DNI of %.0f W/m2 (--cloud-depth forecast%s)",
				k, wx->observed.dni_w_m2, bound);
		else
			cli_err("cloud depth: the genera's (%s)",
				o->cloud_depth_genus ? "--cloud-depth genus"
				: !wx->observed.has_radiation
					? "no forecast radiation at the state's time"
					: "not fitted or needing no change: see --cloud-depth");
	}
	if (o->sky_level == CS_SKY_LEVEL_INEICHEN)
		cli_err("sky level: %.3g times Preetham's, the Ineichen-Perez clear sky's diffuse "
			"light (--sky-level ineichen)", sc->sky_level_scale);
	else
		cli_err("sky level: Preetham's (--sky-level preetham)");
	char fx[256] = "";
	size_t k = 0;
	for (int b = 0; cs_effect_name(1u << b) && k < sizeof fx; b++)
		if (sc->effects & (1u << b))
			k += (size_t)snprintf(fx + k, sizeof fx - k, "%s%s", k ? " " : "",
					      cs_effect_name(1u << b));
	cli_err("effects: %s", fx);
	cli_err("quality %s: %d steps, %d light steps, %d multiple-scattering octaves, "
		"%d haze steps%s%s%s%s%s", o->quality, r->settings.steps, r->settings.light_steps,
		r->settings.ms_octaves, r->settings.haze_steps,
		r->settings.heap_towers ? ", heaps lit as towers" : "",
		r->settings.deck_lattice == CS_DECK_EXCHANGE	 ? ", decks' lattice with the exchange"
		: r->settings.deck_lattice == CS_DECK_DIFFUSION ? ", decks' lattice"
								 : "",
		r->settings.ground_sky == CS_GROUND_SKY_DOME	? ", the ground's sky a dome"
		: r->settings.ground_sky == CS_GROUND_SKY_FIELD ? ", the ground's sky a field"
								: "",
		r->settings.ambient ? "" : ", no ambient", r->settings.jitter > 0 ? "" : ", no jitter");
}

static void report_times(const struct cs_cloudrender_opts *o, const struct cs_cloudrender_result *r)
{
	if (!o->reference && (CS_LIGHT_CACHED(r->settings.light_march) || r->stats.cache_volumes > 0)) {
		char rule[80] = "cache";
		if (!CS_LIGHT_CACHED(r->settings.light_march))
			snprintf(rule, sizeof rule, "the towers' diffused light");
		else if (r->settings.light_march == CS_LIGHT_AUTO)
			snprintf(rule, sizeof rule, "auto: built where the frame has a pixel for %.0f cells",
				 CS_AUTO_CELLS_PER_PIXEL);
		cli_err("light cache: %d volume%s, %.2f million cells (%s)", r->stats.cache_volumes,
			r->stats.cache_volumes == 1 ? "" : "s", r->stats.cache_cells / 1e6, rule);
	}
	if (!o->reference)
		cli_err("ground's diffuse light: %s", cs_ground_lit_name(r->stats.ground_lit));
	double total = r->t_noise_s + r->t_scene_s + r->t_render_s + r->t_irradiance_s +
		       r->t_write_s;
	cli_err("time: noise %.2f s, scene %.2f s, render %.2f s, irradiance %.2f s, "
		"write %.2f s, total %.2f s", r->t_noise_s, r->t_scene_s, r->t_render_s,
		r->t_irradiance_s, r->t_write_s, total);
}

static void parse_pair(const char *opt, const char *s, double *a, double *b,
		       double alo, double ahi, double blo, double bhi)
{
	char buf[128];
	const char *comma = strchr(s, ',');
	if (comma == NULL || (size_t)(comma - s) >= sizeof buf)
		cli_usage_error("%s: expected two comma-separated numbers, not '%s'", opt, s);
	memcpy(buf, s, (size_t)(comma - s));
	buf[comma - s] = '\0';
	*a = cli_double(opt, buf, alo, ahi);
	*b = cli_double(opt, comma + 1, blo, bhi);
}

/* GDAL's single-dash -of FORMAT, which getopt would read as -o "f", made
 * the long option --of (an option word only: not a file named after -o,
 * nothing after "--"). */
static void gdal_of(int argc, char **argv)
{
	static char long_of[] = "--of";
	for (int i = 1; i < argc; i++) {
		if (strcmp(argv[i], "--") == 0)
			return;
		if (strcmp(argv[i], "-o") == 0 || strcmp(argv[i], "--output") == 0)
			i++;
		else if (strcmp(argv[i], "-of") == 0)
			argv[i] = long_of;
	}
}

/* The view file: --views FILE, else $XDG_CONFIG_HOME/cloudscape/views
 * ($HOME/.config/cloudscape/views) when it exists (read for --view and
 * --list-views only).  1 if one was read;
 * a file that cannot be read or has a bad line ends the program (1). */
static int load_views(const char *path, struct cs_viewset *set)
{
	char def[4096];
	if (path == NULL) {
		const char *xdg = getenv("XDG_CONFIG_HOME"), *home = getenv("HOME");
		if (xdg && xdg[0] == '/')
			snprintf(def, sizeof def, "%s/cloudscape/views", xdg);
		else if (home && home[0])
			snprintf(def, sizeof def, "%s/.config/cloudscape/views", home);
		else
			return 0;
		if (access(def, F_OK) != 0)
			return 0;
		path = def;
	}
	if (cs_viewset_read(path, set) != CS_OK) {
		cli_err("--views: %s", cs_errmsg());
		exit(EXIT_DATA);
	}
	return 1;
}

/* The views the run knows (o->views), read when a view is named or listed
 * (a bad default file does not stop other renders). */
static void resolve_views(struct cs_cloudrender_opts *o, const char *path, int list,
			  struct cs_viewset *set)
{
	if ((path || o->view || list) && load_views(path, set))
		o->views = set;
}

/* LAT,LON,ALT_M of --look-at. */
static void parse_look_at(const char *s, struct cs_cloudrender_opts *o)
{
	char buf[256];
	const char *c2 = strrchr(s, ',');
	int commas = 0;
	for (const char *p = s; *p; p++)
		commas += *p == ',';
	if (commas != 2 || (size_t)(c2 - s) >= sizeof buf)
		cli_usage_error("--look-at: expected LAT,LON,ALT_M (degrees, degrees, metres "
				"above sea level), not '%s'", s);
	memcpy(buf, s, (size_t)(c2 - s));
	buf[c2 - s] = '\0';
	parse_pair("--look-at", buf, &o->look_at_lat_deg, &o->look_at_lon_deg, -90.0, 90.0,
		   -180.0, 180.0);
	o->look_at_alt_m = cli_double("--look-at", c2 + 1, -500.0, 100000.0);
	o->have_look_at = 1;
}

/* The easier cameras' rules, once every option is read. */
static void check_easy_camera(const struct cs_cloudrender_opts *o, const char *camera_latlon)
{
	if (o->view && cs_viewset_find(o->views, o->view) == NULL)
		cli_usage_error("--view: unknown view '%s' (see --list-views)", o->view);
	if (o->have_look && o->have_look_at)
		cli_usage_error("--look and --look-at exclude each other: give one");
	if (camera_latlon && !o->have_camera_agl)
		cli_usage_error("--camera: expected three comma-separated numbers LAT,LON,ALT_M "
				"(degrees, degrees, metres above sea level), got 2 in '%s': the "
				"altitude is missing, e.g. --camera 46.9,7.4,600 (or give "
				"--camera-agl M)", camera_latlon);
	if (o->have_camera && !camera_latlon && o->have_camera_agl)
		cli_usage_error("--camera LAT,LON,ALT_M and --camera-agl both set the height: "
				"give --camera LAT,LON with --camera-agl");
}

/* the easier cameras' options (--camera-agl, --look-at, --views) */
enum { OPT_CAMERA_AGL = 600, OPT_LOOK_AT, OPT_VIEWS };

enum {
	OPT_WX = 256, OPT_NOISE, OPT_NOISE_SIZE, OPT_TIME, OPT_VIEW, OPT_LIST_VIEWS,
	OPT_CAMERA, OPT_LOOK, OPT_FOV, OPT_SIZE, OPT_QUALITY, OPT_STEPS,
	OPT_LIGHT_STEPS, OPT_MS, OPT_NO_AMBIENT, OPT_NO_JITTER, OPT_SEED,
	OPT_EXPOSURE, OPT_STATS, OPT_VERSION, OPT_TERRAIN, OPT_TERRAIN_COLOR,
	OPT_PROJECTION, OPT_HAZE_STEPS, OPT_TERRAIN_CPT, OPT_INTEGRATOR, OPT_SPP, OPT_MAX_BOUNCES,
	OPT_NO_HAZE, OPT_MARCH, OPT_LIGHT_MARCH, OPT_SOURCE_EVERY, OPT_TOWER_CELL, OPT_HEAP_TOWERS, OPT_DECK_LATTICE, OPT_GROUND_SKY, OPT_MAX_STEPS, OPT_MIN_T, OPT_OUTPUT_FORMAT,
	OPT_PNG16, OPT_FLOAT, OPT_JPEG_QUALITY, OPT_NO_CLOBBER,
	OPT_DEVICE, OPT_DEVICE_BENCH, /* the GPU renderer */
	OPT_CLOUD_DEPTH,
	OPT_SKY_LEVEL,
};

/* Where it rendered (with -v): the CPU's kernel, or the GPU and, with
 * --device-bench, the benchmark's figures. */
static void report_device(const struct cs_cloudrender_opts *o, const struct cs_cloudrender_result *r)
{
	if (o->device != CS_DEVICE_CUDA) {
		if (cli_verbose && !o->reference)
			cli_err("rendered on the CPU: kernel %s", cs_render_kernel_name());
		return;
	}
	if (cli_verbose)
		cli_err("rendered on %s: kernel %s, %.3f ms", r->device_name,
			r->device_kernel ? r->device_kernel : "none", r->device_kernel_ms);
	if (o->device_bench > 0)
		cli_err("device benchmark: %dx%d, %d warm frames: %.3f ms a frame, %.1f frames/s "
			"(%s, kernel %s)", o->width, o->height, o->device_bench, r->device_frame_ms,
			r->device_frame_ms > 0.0 ? 1000.0 / r->device_frame_ms : 0.0, r->device_name,
			r->device_kernel ? r->device_kernel : "none");
}

int main(int argc, char **argv)
{
	static const struct option longopts[] = {
		{"output", required_argument, NULL, 'o'},
		{"output-format", required_argument, NULL, OPT_OUTPUT_FORMAT},
		{"of", required_argument, NULL, OPT_OUTPUT_FORMAT},
		{"png16", no_argument, NULL, OPT_PNG16},
		{"float", no_argument, NULL, OPT_FLOAT},
		{"jpeg-quality", required_argument, NULL, OPT_JPEG_QUALITY},
		{"no-clobber", no_argument, NULL, OPT_NO_CLOBBER},
		{"wx", required_argument, NULL, OPT_WX},
		{"noise", required_argument, NULL, OPT_NOISE},
		{"noise-size", required_argument, NULL, OPT_NOISE_SIZE},
		{"terrain", required_argument, NULL, OPT_TERRAIN},
		{"terrain-color", required_argument, NULL, OPT_TERRAIN_COLOR},
		{"terrain-cpt", required_argument, NULL, OPT_TERRAIN_CPT},
		{"time", required_argument, NULL, OPT_TIME},
		{"view", required_argument, NULL, OPT_VIEW},
		{"list-views", no_argument, NULL, OPT_LIST_VIEWS},
		{"camera", required_argument, NULL, OPT_CAMERA},
		{"look", required_argument, NULL, OPT_LOOK},
		{"camera-agl", required_argument, NULL, OPT_CAMERA_AGL},
		{"look-at", required_argument, NULL, OPT_LOOK_AT},
		{"views", required_argument, NULL, OPT_VIEWS},
		{"fov", required_argument, NULL, OPT_FOV},
		{"projection", required_argument, NULL, OPT_PROJECTION},
		{"haze-steps", required_argument, NULL, OPT_HAZE_STEPS},
		{"integrator", required_argument, NULL, OPT_INTEGRATOR},
		{"spp", required_argument, NULL, OPT_SPP},
		{"no-haze", no_argument, NULL, OPT_NO_HAZE},
		{"cloud-depth", required_argument, NULL, OPT_CLOUD_DEPTH},
		{"sky-level", required_argument, NULL, OPT_SKY_LEVEL},
		{"march", required_argument, NULL, OPT_MARCH},
		{"light-march", required_argument, NULL, OPT_LIGHT_MARCH},
		{"source-every", required_argument, NULL, OPT_SOURCE_EVERY},
		{"tower-cell", required_argument, NULL, OPT_TOWER_CELL},
		{"heap-towers", required_argument, NULL, OPT_HEAP_TOWERS},
		{"deck-lattice", required_argument, NULL, OPT_DECK_LATTICE},
		{"ground-sky", required_argument, NULL, OPT_GROUND_SKY},
		{"max-steps", required_argument, NULL, OPT_MAX_STEPS},
		{"min-transmittance", required_argument, NULL, OPT_MIN_T},
		{"max-bounces", required_argument, NULL, OPT_MAX_BOUNCES},
		{"size", required_argument, NULL, OPT_SIZE},
		{"quality", required_argument, NULL, OPT_QUALITY},
		{"steps", required_argument, NULL, OPT_STEPS},
		{"light-steps", required_argument, NULL, OPT_LIGHT_STEPS},
		{"ms-octaves", required_argument, NULL, OPT_MS},
		{"no-ambient", no_argument, NULL, OPT_NO_AMBIENT},
		{"no-jitter", no_argument, NULL, OPT_NO_JITTER},
		{"seed", required_argument, NULL, OPT_SEED},
		{"exposure", required_argument, NULL, OPT_EXPOSURE},
		{"threads", required_argument, NULL, 't'},
		{"stats", no_argument, NULL, OPT_STATS},
		{"quiet", no_argument, NULL, 'q'},
		{"verbose", no_argument, NULL, 'v'},
		{"help", no_argument, NULL, 'h'},
		{"version", no_argument, NULL, OPT_VERSION},
		SERIES_LONGOPTS
		{"device", required_argument, NULL, OPT_DEVICE},
		{"device-bench", required_argument, NULL, OPT_DEVICE_BENCH},
		{NULL, 0, NULL, 0},
	};
	struct cs_cloudrender_opts o;
	struct cs_cloudrender_result r;
	int stats = 0;
	int list = 0; /* --list-views */
	const char *camera_latlon = NULL; /* --camera LAT,LON */
	const char *views_path = NULL;
	static struct cs_viewset views; /* static: 30 kB */
	int opt;

	cli_init("cloudrender");
	cs_cloudrender_defaults(&o);
	gdal_of(argc, argv);
	enum cs_out_format of_next = CS_FMT_NONE; /* -of for the -o after it */
	int of_unused = 0;
	while ((opt = getopt_long(argc, argv, "o:t:qvh", longopts, NULL)) != -1) {
		switch (opt) {
		case 'o':
			if (o.noutputs == CS_RENDER_MAX_OUTPUTS)
				cli_usage_error("at most %d outputs", CS_RENDER_MAX_OUTPUTS);
			if (of_next == CS_FMT_NONE && cs_output_format(optarg) == CS_FMT_NONE)
				cli_usage_error("-o %s: unknown format: the name must end in "
						CS_OUT_EXTENSIONS " (or give -of FORMAT before it)",
						optarg);
			o.formats[o.noutputs] = of_next;
			o.outputs[o.noutputs++] = optarg;
			of_unused = 0;
			break;
		case OPT_OUTPUT_FORMAT:
			if ((of_next = cs_output_format_named(optarg)) == CS_FMT_NONE)
				cli_usage_error("-of: unknown format '%s': use " CS_OUT_FORMAT_NAMES,
						optarg);
			of_unused = 1;
			break;
		case OPT_PNG16: o.png16 = 1; break;
		case OPT_FLOAT: o.use_float = 1; break;
		case OPT_JPEG_QUALITY:
			o.jpeg_quality = (int)cli_long("--jpeg-quality", optarg, 1, 100);
			break;
		case OPT_NO_CLOBBER: o.no_clobber = 1; break;
		case OPT_WX: o.wx_path = optarg; break;
		case OPT_NOISE: o.noise_path = optarg; break;
		case OPT_TERRAIN: o.terrain_path = optarg; break;
		case OPT_TERRAIN_COLOR: o.terrain_color_path = optarg; break;
		case OPT_TERRAIN_CPT: o.terrain_cpt_path = optarg; break;
		case OPT_NOISE_SIZE: o.noise_size = (int)cli_long("--noise-size", optarg, 16, 256); break;
		case OPT_TIME:
			o.time_utc = cli_time("--time", optarg);
			o.have_time = 1;
			break;
		case OPT_VIEW: o.view = optarg; break; /* checked once --views is read */
		case OPT_LIST_VIEWS: list = 1; break;
		case OPT_CAMERA_AGL:
			o.camera_agl_m = cli_double("--camera-agl", optarg, 0.0, 100000.0);
			o.have_camera_agl = 1;
			break;
		case OPT_LOOK_AT:
			parse_look_at(optarg, &o);
			break;
		case OPT_VIEWS: views_path = optarg; break;
		case OPT_CAMERA: {
			char buf[256];
			const char *c2 = strrchr(optarg, ',');
			int commas = 0;
			for (const char *p = optarg; *p; p++)
				commas += *p == ',';
			if (commas == 1) { /* LAT,LON: the height from --camera-agl */
				parse_pair("--camera", optarg, &o.cam_lat_deg, &o.cam_lon_deg,
					   -89.9, 89.9, -180.0, 180.0);
				o.have_camera = 1;
				camera_latlon = optarg;
				break;
			}
			camera_latlon = NULL;
			if (commas != 2)
				cli_usage_error("--camera: expected three comma-separated numbers "
						"LAT,LON,ALT_M (degrees, degrees, metres above sea "
						"level), got %d in '%s'%s", commas + 1, optarg,
						commas == 1 ? ": the altitude is missing, e.g. "
						"--camera 46.9,7.4,600" : "");
			if ((size_t)(c2 - optarg) >= sizeof buf)
				cli_usage_error("--camera: expected LAT,LON,ALT_M, not '%s'", optarg);
			memcpy(buf, optarg, (size_t)(c2 - optarg));
			buf[c2 - optarg] = '\0';
			parse_pair("--camera", buf, &o.cam_lat_deg, &o.cam_lon_deg, -89.9, 89.9,
				   -180.0, 180.0);
			o.cam_alt_m = cli_double("--camera", c2 + 1, -500.0, 100000.0);
			o.have_camera = 1;
			break;
		}
		case OPT_LOOK:
			parse_pair("--look", optarg, &o.look_az_deg, &o.look_el_deg, -360.0, 360.0,
				   -90.0, 90.0);
			o.have_look = 1;
			break;
		case OPT_FOV: o.fov_deg = cli_double("--fov", optarg, 1.0, 179.0); break;
		case OPT_HAZE_STEPS:
			o.haze_steps = (int)cli_long("--haze-steps", optarg, 0, 10000);
			break;
		case OPT_PROJECTION:
			if (cs_projection_parse(optarg, &o.projection) != CS_OK)
				cli_usage_error("--projection: %s", cs_errmsg());
			break;
		case OPT_SIZE: {
			char *x = strchr(optarg, 'x');
			if (x == NULL)
				cli_usage_error("--size: expected WxH, not '%s'", optarg);
			*x = '\0';
			/* the library says what a size over the limits would need */
			o.width = (int)cli_long("--size", optarg, 1, 1000000000);
			o.height = (int)cli_long("--size", x + 1, 1, 1000000000);
			*x = 'x';
			break;
		}
		case OPT_QUALITY:
			if (cs_render_quality(optarg, &o.settings) != CS_OK)
				cli_usage_error("--quality: %s", cs_errmsg());
			o.quality = optarg;
			break;
		case OPT_STEPS: o.steps = (int)cli_long("--steps", optarg, 1, 100000); break;
		case OPT_LIGHT_STEPS:
			o.light_steps = (int)cli_long("--light-steps", optarg, 1, 10000);
			break;
		case OPT_MS: o.ms_octaves = (int)cli_long("--ms-octaves", optarg, 1, 4); break;
		case OPT_INTEGRATOR: {
			static const char *const names[] = {"march", "reference", NULL};
			o.reference = cli_choice("--integrator", optarg, names);
			break;
		}
		case OPT_SPP: o.spp = (int)cli_long("--spp", optarg, 1, 1000000); break;
		case OPT_MAX_BOUNCES:
			o.max_bounces = (int)cli_long("--max-bounces", optarg, 0, 1000000);
			break;
		case OPT_NO_HAZE: o.no_haze = 1; break;
		case OPT_CLOUD_DEPTH: {
			static const char *const names[] = {"forecast", "genus", NULL};
			o.cloud_depth_genus = cli_choice("--cloud-depth", optarg, names);
			break;
		}
		case OPT_SKY_LEVEL: {
			/* in enum cs_sky_level's order */
			static const char *const names[] = {"preetham", "ineichen", NULL};
			o.sky_level = (enum cs_sky_level)cli_choice("--sky-level", optarg, names);
			break;
		}
		case OPT_MARCH: {
			/* in CS_MARCH_*'s order */
			static const char *const names[] = {"standard", "naive", "skip", "adaptive", NULL};
			o.march = cli_choice("--march", optarg, names);
			break;
		}
		case OPT_LIGHT_MARCH: {
			/* in CS_LIGHT_*'s order */
			static const char *const names[] = {"uniform", "quadratic", "geometric", "cone",
							    "cache",   "auto",      NULL};
			o.light_march = cli_choice("--light-march", optarg, names);
			break;
		}
		case OPT_TOWER_CELL:
			o.tower_cell_m = cli_double("--tower-cell", optarg, 0.0, 5000.0);
			if (o.tower_cell_m > 0.0 && o.tower_cell_m < 50.0)
				cli_usage_error("--tower-cell: 0 or 50 to 5000 m, not %s", optarg);
			break;
		case OPT_HEAP_TOWERS: {
			static const char *const names[] = {"off", "on", NULL};
			o.heap_towers = cli_choice("--heap-towers", optarg, names);
			break;
		}
		case OPT_DECK_LATTICE: {
			static const char *const names[] = {"off", "diffusion", "exchange", "on", NULL};
			_Static_assert(CS_DECK_COLUMNS == 0 && CS_DECK_DIFFUSION == 1 &&
					       CS_DECK_EXCHANGE == 2,
				       "--deck-lattice's names in the settings' order");
			int c = cli_choice("--deck-lattice", optarg, names);
			o.deck_lattice = c == 3 ? CS_DECK_EXCHANGE : c; /* on: earlier releases' */
			break;
		}
		case OPT_GROUND_SKY: {
			static const char *const names[] = {"columns", "dome", "field", NULL};
			_Static_assert(CS_GROUND_SKY_COLUMNS == 0 && CS_GROUND_SKY_DOME == 1 &&
					       CS_GROUND_SKY_FIELD == 2,
				       "--ground-sky's names in the settings' order");
			o.ground_sky = cli_choice("--ground-sky", optarg, names);
			break;
		}
		case OPT_SOURCE_EVERY:
			o.source_every = (int)cli_long("--source-every", optarg, 1, 2);
			break;
		case OPT_MAX_STEPS: o.max_steps = (int)cli_long("--max-steps", optarg, 1, 1000000); break;
		case OPT_MIN_T:
			o.min_transmittance = cli_double("--min-transmittance", optarg, 0.0, 0.5);
			break;
		case OPT_NO_AMBIENT: o.no_ambient = 1; break;
		case OPT_NO_JITTER: o.no_jitter = 1; break;
		case OPT_SEED: o.seed = cli_long("--seed", optarg, 0, 4294967295L); break;
		case OPT_EXPOSURE:
			if (strcasecmp(optarg, "auto") == 0)
				o.exposure_auto = 1;
			else
				o.exposure_ev = cli_double("--exposure", optarg, -20.0, 20.0);
			break;
		case 't': o.threads = (int)cli_long("--threads", optarg, 1, 256); break;
		case OPT_STATS: stats = o.irradiance = 1; break;
		case 'q': cli_quiet = 1; break;
		case 'v': cli_verbose = 1; break;
		case 'h': /* a bad --view before it is still refused */
			resolve_views(&o, views_path, 0, &views);
			if (o.view && cs_viewset_find(o.views, o.view) == NULL)
				cli_usage_error("--view: unknown view '%s' (see --list-views)",
						o.view);
			usage();
			return EXIT_OK;
		case OPT_VERSION: printf("cloudrender (cloudscape) %s\n", CS_VERSION); return EXIT_OK;
		case OPT_DEVICE:
			if (strcmp(optarg, "cpu") == 0)
				o.device = CS_DEVICE_CPU;
			else if (strcmp(optarg, "cuda") == 0)
				o.device = CS_DEVICE_CUDA;
			else
				cli_usage_error("--device: '%s' is not cpu or cuda", optarg);
			break;
		case OPT_DEVICE_BENCH:
			o.device_bench = (int)cli_long("--device-bench", optarg, 1, 100000);
			break;
		default:
			if (series_option(opt, optarg, &o))
				break;
			fprintf(stderr, "Try 'cloudrender --help' for more information.\n");
			return EXIT_USAGE;
		}
	}
	if (optind < argc)
		cli_usage_error("unexpected argument '%s'", argv[optind]);
	resolve_views(&o, views_path, list, &views);
	if (list) {
		list_views(o.views);
		return EXIT_OK;
	}
	check_easy_camera(&o, camera_latlon);
	if (of_unused)
		cli_usage_error("-of applies to the -o outputs after it: none follows");
	if (o.terrain_color_path && !o.terrain_path)
		cli_usage_error("--terrain-color needs --terrain");
	if (o.terrain_cpt_path && !o.terrain_path)
		cli_usage_error("--terrain-cpt needs --terrain");
	if (o.terrain_cpt_path && o.terrain_color_path)
		cli_usage_error("--terrain-color and --terrain-cpt exclude each other");
	if (o.noutputs == 0)
		cli_usage_error("no output: give -o FILE.png (or .exr, .tif, .jpg)");
	int to_stdout = 0;
	for (int i = 0; i < o.noutputs; i++)
		to_stdout += strcmp(o.outputs[i], "-") == 0;
	if (to_stdout > 1)
		cli_usage_error("only one output can go to standard output");
	if (o.wx_path && o.noise_path && strcmp(o.wx_path, "-") == 0 &&
	    strcmp(o.noise_path, "-") == 0)
		cli_usage_error("--wx - and --noise - cannot both read standard input");

	struct series_report rep = {&o, stats, "rendering", 0, 0, -1.0, -1.0};
	o.progress = cli_progress;
	o.progress_user = rep.label;
	o.frame = frame_report;
	o.frame_user = &rep;
	if (cli_verbose) {
		o.ready = describe;
		o.ready_user = &o;
	}
	o.cancel = &cli_stop_signal;
	cli_catch_stop_signals();
	int rc = cs_cloudrender_run(&o, &r);
	cli_progress_done();
	if (cli_stop_signal) { /* the frames written are whole; nothing else is left */
		cli_err("interrupted: %d frames written whole, no other begun", rep.rendered);
		cs_cloudrender_result_free(&r);
		return cli_die_of_stop_signal();
	}
	if (cli_verbose && rep.rendered + rep.skipped > 1)
		cli_err("%d frames rendered in %.1f s (%.2f s a frame), %d skipped", rep.rendered,
			rep.rendered ? rep.last_s - rep.first_s : 0.0,
			rep.rendered ? (rep.last_s - rep.first_s) / rep.rendered : 0.0, rep.skipped);
	if (rc != CS_OK) {
		cli_err("%s", cs_errmsg());
		cs_cloudrender_result_free(&r);
		return rc == CS_EINVAL ? EXIT_USAGE : EXIT_DATA;
	}
	/* legal, but almost certainly not what was meant */
	if (!cli_quiet && r.camera_site_km > 300.0)
		cli_err("warning: the camera is %.0f km from the weather site (%s): "
			"the weather describes the sky over the site", r.camera_site_km,
			r.wx.site.name[0] ? r.wx.site.name : "unnamed");
	if (!cli_quiet && r.camera_terrain_km > 300.0)
		cli_err("warning: the camera is %.0f km from the terrain's centre", r.camera_terrain_km);
	if (cli_verbose && rep.rendered > 0)
		report_times(&o, &r);
	report_device(&o, &r);
	cs_cloudrender_result_free(&r);
	return EXIT_OK;
}
