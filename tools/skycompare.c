/* skycompare - hold a render against a photograph of the same sky. */
#include "cli.h"

#include "apps/skycompare_run.h"
#include "core/err.h"

#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifndef CS_VERSION
#define CS_VERSION "unknown"
#endif

static void usage(void)
{
	printf("Usage: skycompare [options] RENDER PHOTO\n"
	       "       skycompare [options] --series RENDER_PATTERN PHOTO_PATTERN\n"
	       "Hold a render against a photograph of the same sky: the cloud fraction\n"
	       "(red/blue ratio), luminance, colour and histograms of each picture's sky,\n"
	       "their distances, and one verdict.  Pictures: PNG, OpenEXR, or anything\n"
	       "GDAL reads (JPEG webcam frames); both are compared on one grid.\n"
	       "\n"
	       "  -o, --output FILE.png  side by side: render | photo, their cloud maps below\n"
	       "                         (cloud white, clear sky blue, not sky black)\n"
	       "      --overlay FILE.png split screen: render left of a divider, photo right\n"
	       "      --split FRAC       the divider's position, 0..1 of the width (default 0.5)\n"
	       "      --blend W          make the overlay a blend, the photo's weight 0..1\n"
	       "      --diff FILE.png    false colour: render minus photo in display luminance\n"
	       "                         (red: render brighter, blue: darker; grey: not sky)\n"
	       "      --diff-range L     levels at full colour, 1..255 (default 32)\n"
	       "      --threshold RB     R/B on linear RGB at or above which a pixel is cloud,\n"
	       "                         0.05..5 (default 0.75)\n"
	       "      --mask FILE        the photo's sky: a picture of its size, white = sky\n"
	       "      --horizon ROW      the photo's sky: the rows above ROW (0 = top)\n"
	       "      --render-horizon ROW  the render's sky: only the rows above ROW\n"
	       "                         (with its depth mask: the haze near the horizon)\n"
	       "      --sky-all          every pixel of both pictures is sky\n"
	       "                         (default: an EXR's depth and alpha, else an\n"
	       "                         automatic estimate: see skycompare(1))\n"
	       "      --crop X,Y,W,H     compare the photo's window W x H at X,Y (pixels)\n"
	       "      --fov R,P          horizontal fields of view of render and photo (deg):\n"
	       "                         the photo's middle part the render's camera sees\n"
	       "      --grid WxH         the common grid (default: the render's size)\n"
	       "      --exposure EV[,EV] display exposure of an OpenEXR render[, photo],\n"
	       "                         stops, -20..20 (default 0, as cloudrender's PNG)\n"
	       "      --undo-tonemap     the render is a PNG of cloudrender's (at --exposure):\n"
	       "                         classify the radiance its display transform came from\n"
	       "      --series           RENDER and PHOTO are printf patterns (%%05d): one line\n"
	       "                         per pair and a summary; -o, --overlay, --diff too\n"
	       "      --first N          the series' first index (default 0, or 1 when the\n"
	       "                         render for 0 is absent)\n"
	       "      --last N           the series' last index (default: until a render is\n"
	       "                         absent)\n"
	       "      --json             the report as JSON (a series: JSON Lines)\n"
	       "  -q, --quiet            no warnings\n"
	       "  -v, --verbose          more in the report: the histograms, 16 bins\n"
	       "  -h, --help             this help\n"
	       "      --version          print the version\n"
	       "\n"
	       "Exit status: 0 success, 1 data or runtime error, 2 usage error.\n"
	       "See skycompare(1) and cloudrender(1).\n");
}

/* ---- the report ------------------------------------------------------------ */

static void jnum(int digits, double v)
{
	if (isfinite(v))
		printf("%.*f", digits, v);
	else
		fputs("null", stdout);
}

static void jstr(const char *s)
{
	putchar('"');
	for (; *s; s++) {
		unsigned char c = (unsigned char)*s;
		if (c == '"' || c == '\\')
			printf("\\%c", c);
		else if (c < 0x20)
			printf("\\u%04x", c);
		else
			putchar(c);
	}
	putchar('"');
}

static void json_side(const char *file, int w, int h, const char *sky,
		      const struct cs_sky_stats *s, int hist)
{
	static const char ch[3] = {'r', 'g', 'b'};
	printf("{\"file\":");
	jstr(file);
	printf(",\"size\":[%d,%d],\"sky\":{\"method\":\"%s\",\"pixels\":%ld,\"fraction\":%.4f},"
	       "\"cloud_fraction\":%.4f,\"cloud_pixels\":%ld,\"mean_luminance\":%.5f,"
	       "\"median_luminance\":%.5f,", w, h, sky, s->sky_pixels,
	       s->pixels ? (double)s->sky_pixels / s->pixels : 0.0, s->cls.cloud_fraction,
	       s->cls.cloud_pixels, s->mean_lum, s->median_lum);
	if (s->mean_lum_kcd_m2 >= 0.0)
		printf("\"mean_luminance_kcd_m2\":%.6g,", s->mean_lum_kcd_m2);
	printf("\"mean_rgb\":[%.2f,%.2f,%.2f],\"median_rgb\":[%.0f,%.0f,%.0f]", s->mean_rgb[0],
	       s->mean_rgb[1], s->mean_rgb[2], s->median_rgb[0], s->median_rgb[1], s->median_rgb[2]);
	if (hist) {
		printf(",\"histogram\":{");
		for (int c = 0; c < 3; c++) {
			printf("%s\"%c\":[", c ? "," : "", ch[c]);
			for (int k = 0; k < CS_SKY_BINS; k++)
				printf("%s%ld", k ? "," : "", s->hist[c][k]);
			putchar(']');
		}
		putchar('}');
	}
	putchar('}');
}

static const char *const verdict_word[3] = {"match", "fair", "poor"};

static void json_pair(const struct cs_skycompare_opts *o, const struct cs_skycompare_pair *p,
		      int series)
{
	printf("{\"program\":\"skycompare\",");
	if (series)
		printf("\"index\":%ld,", p->index);
	if (p->status != CS_OK) {
		printf("\"render\":");
		jstr(p->render);
		printf(",\"photo\":");
		jstr(p->photo);
		printf(",\"%s\":", p->status == 1 ? "missing" : "error");
		jstr(p->message);
		printf("}\n");
		return;
	}
	const struct cs_sky_diff *d = &p->diff;
	printf("\"rb_threshold\":%.4g,\"grid\":[%d,%d],\"render\":", o->rb_threshold, p->grid_w,
	       p->grid_h);
	json_side(p->render, p->render_w, p->render_h, p->render_sky, &p->render_stats, !series);
	printf(",\"photo\":");
	json_side(p->photo, p->photo_w, p->photo_h, p->photo_sky, &p->photo_stats, !series);
	printf(",\"difference\":{\"common_sky_pixels\":%ld,\"cloud_fraction\":%.4f,"
	       "\"cloud_disagreement\":%.4f,\"mean_luminance\":%.5f,\"luminance_ratio\":",
	       d->common_pixels, d->d_cloud_fraction, d->cloud_disagree, d->d_mean_lum);
	jnum(5, d->lum_ratio);
	printf(",\"mean_level\":[%.3f,%.3f,%.3f],\"mean_abs_level\":%.3f,\"emd_levels\":{",
	       d->mean_d_level[0], d->mean_d_level[1], d->mean_d_level[2], d->mean_abs_d_level);
	static const char *const ch[4] = {"r", "g", "b", "mean"};
	for (int c = 0; c < 4; c++) {
		printf("%s\"%s\":", c ? "," : "", ch[c]);
		jnum(4, c < 3 ? d->emd[c] : d->emd_mean);
	}
	printf("},\"chi2\":{");
	for (int c = 0; c < 4; c++) {
		printf("%s\"%s\":", c ? "," : "", ch[c]);
		jnum(5, c < 3 ? d->chi2[c] : d->chi2_mean);
	}
	printf("}},\"verdict\":\"%s\",\"verdict_text\":", verdict_word[p->verdict]);
	jstr(p->verdict_text);
	printf("}\n");
}

/* A 16-bin histogram as a row of counts per mille. */
static void text_hist(const char *label, const long *h, long total)
{
	printf("%-20s", label);
	for (int b = 0; b < 16; b++) {
		long s = 0;
		for (int k = 0; k < 16; k++)
			s += h[b * 16 + k];
		printf(" %3.0f", total ? 1000.0 * s / total : 0.0);
	}
	putchar('\n');
}

static void text_pair(const struct cs_skycompare_opts *o, const struct cs_skycompare_pair *p)
{
	const struct cs_sky_stats *a = &p->render_stats, *b = &p->photo_stats;
	const struct cs_sky_diff *d = &p->diff;
	char s1[64], s2[64];
	printf("%-20s%-24s%-24s%s\n", "", "render", "photo", "render - photo");
	printf("%-20s%-24.23s%-24.23s\n", "file", p->render, p->photo);
	snprintf(s1, sizeof s1, "%dx%d", p->render_w, p->render_h);
	snprintf(s2, sizeof s2, "%dx%d", p->photo_w, p->photo_h);
	printf("%-20s%-24s%-24sgrid %dx%d\n", "size", s1, s2, p->grid_w, p->grid_h);
	snprintf(s1, sizeof s1, "%s, %.1f %%", p->render_sky,
		 a->pixels ? 100.0 * a->sky_pixels / a->pixels : 0.0);
	snprintf(s2, sizeof s2, "%s, %.1f %%", p->photo_sky,
		 b->pixels ? 100.0 * b->sky_pixels / b->pixels : 0.0);
	printf("%-20s%-24s%-24sboth %.1f %%\n", "sky", s1, s2,
	       a->pixels ? 100.0 * d->common_pixels / a->pixels : 0.0);
	printf("%-20s%-24.3f%-24.3f%+.3f (R/B >= %g; %.1f %% of pixels differ)\n",
	       "cloud fraction", a->cls.cloud_fraction, b->cls.cloud_fraction, d->d_cloud_fraction,
	       o->rb_threshold, 100.0 * d->cloud_disagree);
	printf("%-20s%-24.4f%-24.4f", "mean luminance", a->mean_lum, b->mean_lum);
	if (isfinite(d->lum_ratio))
		printf("x%.3f\n", d->lum_ratio);
	else
		printf("-\n");
	printf("%-20s%-24.4f%-24.4f%+.4f\n", "median luminance", a->median_lum, b->median_lum,
	       a->median_lum - b->median_lum);
	snprintf(s1, sizeof s1, "%.0f %.0f %.0f", a->mean_rgb[0], a->mean_rgb[1], a->mean_rgb[2]);
	snprintf(s2, sizeof s2, "%.0f %.0f %.0f", b->mean_rgb[0], b->mean_rgb[1], b->mean_rgb[2]);
	printf("%-20s%-24s%-24s%+.1f %+.1f %+.1f per pixel\n", "mean colour", s1, s2,
	       d->mean_d_level[0], d->mean_d_level[1], d->mean_d_level[2]);
	snprintf(s1, sizeof s1, "%.0f %.0f %.0f", a->median_rgb[0], a->median_rgb[1],
		 a->median_rgb[2]);
	snprintf(s2, sizeof s2, "%.0f %.0f %.0f", b->median_rgb[0], b->median_rgb[1],
		 b->median_rgb[2]);
	printf("%-20s%-24s%-24s|diff| %.1f levels\n", "median colour", s1, s2, d->mean_abs_d_level);
	if (isfinite(d->emd_mean)) {
		printf("%-20s%.2f %.2f %.2f levels (mean %.2f)\n", "EMD R G B", d->emd[0],
		       d->emd[1], d->emd[2], d->emd_mean);
		printf("%-20s%.4f %.4f %.4f (mean %.4f)\n", "chi2 R G B", d->chi2[0], d->chi2[1],
		       d->chi2[2], d->chi2_mean);
	} else {
		printf("%-20s- (a picture without sky)\n%-20s-\n", "EMD R G B", "chi2 R G B");
	}
	if (cli_verbose) {
		static const char *const lab[2][3] = {{"render R", "render G", "render B"},
						      {"photo R", "photo G", "photo B"}};
		printf("histograms, per mille of the sky in 16 bins of 16 levels:\n");
		for (int s = 0; s < 2; s++)
			for (int c = 0; c < 3; c++)
				text_hist(lab[s][c], (s ? b : a)->hist[c], (s ? b : a)->sky_pixels);
	}
	printf("verdict: %s\n", p->verdict_text);
}

static void text_line(const struct cs_skycompare_pair *p)
{
	if (p->status != CS_OK) {
		printf("%6ld  %s: %s\n", p->index, p->status == 1 ? "missing" : "error", p->message);
		return;
	}
	const struct cs_sky_diff *d = &p->diff;
	char lum[32] = "-", emd[32] = "-";
	if (isfinite(d->lum_ratio))
		snprintf(lum, sizeof lum, "x%.3f", d->lum_ratio);
	if (isfinite(d->emd_mean))
		snprintf(emd, sizeof emd, "%5.1f", d->emd_mean);
	printf("%6ld  cloud %.3f %.3f %+.3f  lum %s  EMD %s  %s\n", p->index,
	       p->render_stats.cls.cloud_fraction, p->photo_stats.cls.cloud_fraction,
	       d->d_cloud_fraction, lum, emd, verdict_word[p->verdict]);
}

static void summary(const struct cs_skycompare_result *r, int json)
{
	if (json) {
		printf("{\"program\":\"skycompare\",\"summary\":{\"pairs\":%d,\"compared\":%d,"
		       "\"missing\":%d,\"failed\":%d,\"cloud_fraction_mean_difference\":%.4f,"
		       "\"cloud_fraction_mean_abs_difference\":%.4f,\"luminance_ratio_geomean\":",
		       r->npairs, r->compared, r->missing, r->failed, r->mean_d_cloud,
		       r->mean_abs_d_cloud);
		jnum(5, r->mean_lum_ratio);
		printf(",\"emd_levels_mean\":");
		jnum(4, r->mean_emd);
		printf(",\"verdicts\":{\"match\":%d,\"fair\":%d,\"poor\":%d}}}\n",
		       r->verdicts[0], r->verdicts[1], r->verdicts[2]);
		return;
	}
	printf("summary: %d pairs, %d compared, %d missing, %d failed; cloud fraction render - "
	       "photo %+.3f (mean |difference| %.3f); luminance x%.3f (geometric mean); EMD %.1f "
	       "levels; %d match, %d fair, %d poor\n",
	       r->npairs, r->compared, r->missing, r->failed, r->mean_d_cloud, r->mean_abs_d_cloud,
	       r->mean_lum_ratio, r->mean_emd, r->verdicts[0], r->verdicts[1], r->verdicts[2]);
}

/* ---- options ----------------------------------------------------------------- */

static void parse_size(const char *opt, char *s, int *w, int *h)
{
	char *x = strchr(s, 'x');
	if (x == NULL)
		cli_usage_error("%s: expected WxH, not '%s'", opt, s);
	*x = '\0';
	*w = (int)cli_long(opt, s, 1, 16384);
	*h = (int)cli_long(opt, x + 1, 1, 16384);
	*x = 'x';
}

enum {
	OPT_OVERLAY = 256, OPT_SPLIT, OPT_BLEND, OPT_DIFF, OPT_DIFF_RANGE, OPT_THRESHOLD,
	OPT_MASK, OPT_HORIZON, OPT_RENDER_HORIZON, OPT_SKY_ALL, OPT_CROP, OPT_FOV, OPT_GRID, OPT_EXPOSURE,
	OPT_UNDO_TONEMAP, OPT_SERIES, OPT_FIRST, OPT_LAST, OPT_JSON, OPT_VERSION,
};

int main(int argc, char **argv)
{
	static const struct option longopts[] = {
		{"output", required_argument, NULL, 'o'},
		{"overlay", required_argument, NULL, OPT_OVERLAY},
		{"split", required_argument, NULL, OPT_SPLIT},
		{"blend", required_argument, NULL, OPT_BLEND},
		{"diff", required_argument, NULL, OPT_DIFF},
		{"diff-range", required_argument, NULL, OPT_DIFF_RANGE},
		{"threshold", required_argument, NULL, OPT_THRESHOLD},
		{"mask", required_argument, NULL, OPT_MASK},
		{"horizon", required_argument, NULL, OPT_HORIZON},
		{"render-horizon", required_argument, NULL, OPT_RENDER_HORIZON},
		{"sky-all", no_argument, NULL, OPT_SKY_ALL},
		{"crop", required_argument, NULL, OPT_CROP},
		{"fov", required_argument, NULL, OPT_FOV},
		{"grid", required_argument, NULL, OPT_GRID},
		{"exposure", required_argument, NULL, OPT_EXPOSURE},
		{"undo-tonemap", no_argument, NULL, OPT_UNDO_TONEMAP},
		{"series", no_argument, NULL, OPT_SERIES},
		{"first", required_argument, NULL, OPT_FIRST},
		{"last", required_argument, NULL, OPT_LAST},
		{"json", no_argument, NULL, OPT_JSON},
		{"quiet", no_argument, NULL, 'q'},
		{"verbose", no_argument, NULL, 'v'},
		{"help", no_argument, NULL, 'h'},
		{"version", no_argument, NULL, OPT_VERSION},
		{NULL, 0, NULL, 0},
	};
	struct cs_skycompare_opts o;
	struct cs_skycompare_result r;
	int series = 0, json = 0, opt, have_split = 0, have_range = 0;

	cli_init("skycompare");
	cs_skycompare_defaults(&o);
	while ((opt = getopt_long(argc, argv, "o:qvh", longopts, NULL)) != -1) {
		switch (opt) {
		case 'o': o.side_path = optarg; break;
		case OPT_OVERLAY: o.overlay_path = optarg; break;
		case OPT_SPLIT:
			o.split = cli_double("--split", optarg, 0.0, 1.0);
			have_split = 1;
			break;
		case OPT_BLEND: o.blend = cli_double("--blend", optarg, 0.0, 1.0); break;
		case OPT_DIFF: o.diff_path = optarg; break;
		case OPT_DIFF_RANGE:
			o.diff_range = cli_double("--diff-range", optarg, 1.0, 255.0);
			have_range = 1;
			break;
		case OPT_THRESHOLD: o.rb_threshold = cli_double("--threshold", optarg, 0.05, 5.0); break;
		case OPT_MASK: o.mask_path = optarg; break;
		case OPT_HORIZON: o.horizon_row = (int)cli_long("--horizon", optarg, 0, 16384); break;
		case OPT_RENDER_HORIZON:
			o.render_horizon_row = (int)cli_long("--render-horizon", optarg, 0, 16384);
			break;
		case OPT_SKY_ALL: o.sky_all = 1; break;
		case OPT_CROP: {
			double c[4];
			cli_double_list("--crop", optarg, 0.0, 1e6, 4, c);
			for (int k = 0; k < 4; k++) {
				if (c[k] != floor(c[k]))
					cli_usage_error("--crop: %g is not a whole number of pixels", c[k]);
				o.crop[k] = (int)c[k];
			}
			if (o.crop[2] < 1 || o.crop[3] < 1)
				cli_usage_error("--crop: the window must be at least 1x1");
			o.have_crop = 1;
			break;
		}
		case OPT_FOV: cli_double_list("--fov", optarg, 1.0, 360.0, 2, o.fov_deg); break;
		case OPT_GRID: parse_size("--grid", optarg, &o.grid_w, &o.grid_h); break;
		case OPT_EXPOSURE:
			if (strchr(optarg, ','))
				cli_double_list("--exposure", optarg, -20.0, 20.0, 2, o.exposure_ev);
			else
				o.exposure_ev[0] = o.exposure_ev[1] =
					cli_double("--exposure", optarg, -20.0, 20.0);
			break;
		case OPT_UNDO_TONEMAP: o.undo_tonemap = 1; break;
		case OPT_SERIES: series = 1; break;
		case OPT_FIRST: o.first = cli_long("--first", optarg, 0, 999999999); break;
		case OPT_LAST: o.last = cli_long("--last", optarg, 0, 999999999); break;
		case OPT_JSON: json = 1; break;
		case 'q': cli_quiet = 1; break;
		case 'v': cli_verbose = 1; break;
		case 'h': usage(); return EXIT_OK;
		case OPT_VERSION: printf("skycompare (cloudscape) %s\n", CS_VERSION); return EXIT_OK;
		default:
			fprintf(stderr, "Try 'skycompare --help' for more information.\n");
			return EXIT_USAGE;
		}
	}
	if (argc - optind != 2)
		cli_usage_error(argc - optind < 2 ? "give a render and a photo%s"
						  : "unexpected argument '%s'",
				argc - optind < 2 ? (series ? " pattern" : "") : argv[optind + 2]);
	if ((have_split || o.blend >= 0.0) && !o.overlay_path)
		cli_usage_error("--%s shapes the overlay: give --overlay FILE.png",
				have_split ? "split" : "blend");
	if (have_split && o.blend >= 0.0)
		cli_usage_error("--split and --blend: the overlay is one or the other");
	if (have_range && !o.diff_path)
		cli_usage_error("--diff-range needs --diff FILE.png");
	if (o.mask_path && o.horizon_row >= 0)
		cli_usage_error("--mask and --horizon both give the photo's sky: choose one");
	if (o.sky_all && (o.mask_path || o.horizon_row >= 0 || o.render_horizon_row >= 0))
		cli_usage_error("--sky-all and --%s contradict each other",
				o.mask_path ? "mask" : o.horizon_row >= 0 ? "horizon" : "render-horizon");
	if (!series && (o.first >= 0 || o.last >= 0))
		cli_usage_error("--first and --last need --series");
	if (o.first >= 0 && o.last >= 0 && o.last < o.first)
		cli_usage_error("--last %ld is before --first %ld", o.last, o.first);
	if (series) {
		o.series_render = argv[optind];
		o.series_photo = argv[optind + 1];
		o.progress = cli_progress;
		o.progress_user = "comparing";
	} else {
		o.render_path = argv[optind];
		o.photo_path = argv[optind + 1];
	}
	int rc = cs_skycompare_run(&o, &r);
	cli_progress_done();
	if (rc == CS_EINVAL) {
		cli_usage_error("%s", cs_errmsg());
	} else if (rc != CS_OK && !series) {
		cli_err("%s", cs_errmsg());
		cs_skycompare_result_free(&r);
		return EXIT_DATA;
	}
	for (int i = 0; i < r.npairs; i++) {
		const struct cs_skycompare_pair *p = &r.pairs[i];
		if (!cli_quiet && p->status == CS_OK && p->aspect_differs)
			cli_err("warning: %s: the photo's %dx%d window is stretched onto the %dx%d grid "
				"(give --crop or --fov)", p->photo, p->photo_w, p->photo_h, p->grid_w,
				p->grid_h);
		if (json)
			json_pair(&o, p, series);
		else if (series)
			text_line(p);
		else
			text_pair(&o, p);
	}
	if (series && r.npairs)
		summary(&r, json);
	if (rc != CS_OK)
		cli_err("%s", cs_errmsg());
	int status = rc != CS_OK || r.failed ? EXIT_DATA : EXIT_OK;
	if (series && r.failed && rc == CS_OK)
		cli_err("%d of %d pairs could not be compared", r.failed, r.npairs);
	cs_skycompare_result_free(&r);
	return status;
}
