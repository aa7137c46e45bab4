/* skycompare_run.h - the skycompare program as a library call: a render
 * held against a photograph of the same sky (or a series of them). */
#ifndef CS_SKYCOMPARE_RUN_H
#define CS_SKYCOMPARE_RUN_H

#include "io/skystats.h"

/* The verdict's limits (documented in skycompare(1)): a pair "matches" when
 * the cloud fractions differ by at most CS_VERDICT_CLOUD and the mean earth
 * mover's distance of the three channels is at most CS_VERDICT_EMD display
 * levels; it is "fair" within the _FAIR limits, else "poor".  Mean
 * luminances within CS_VERDICT_LUM of each other are "as bright". */
#define CS_VERDICT_CLOUD 0.10
#define CS_VERDICT_EMD 8.0
#define CS_VERDICT_CLOUD_FAIR 0.25
#define CS_VERDICT_EMD_FAIR 24.0
#define CS_VERDICT_LUM 0.15

enum cs_verdict { CS_MATCH = 0, CS_FAIR = 1, CS_POOR = 2 };

struct cs_skycompare_opts {
	const char *render_path, *photo_path; /* one pair */
	const char *series_render, *series_photo; /* or printf patterns (%d, %05d) */
	long first;               /* series: first index; -1: 0, or 1 if 0's render is absent */
	long last;                /* series: last index; -1: until a render is absent */
	double rb_threshold;      /* R/B on linear RGB at or above which a pixel is cloud */
	double exposure_ev[2];    /* display exposure of an OpenEXR render, photo */
	int undo_tonemap;         /* the render is cloudrender's PNG: classify the radiance
				   * behind it (cs_picture_undo_display at exposure_ev[0]) */
	const char *mask_path;    /* the photo's sky: a mask picture, or NULL */
	int horizon_row;          /* the photo's sky: rows above this one; -1: none */
	int render_horizon_row;   /* the render's sky: only rows above this one; -1: all */
	int sky_all;              /* every pixel of both is sky */
	int have_crop;
	int crop[4];              /* the photo's window x, y, w, h (pixels) */
	double fov_deg[2];        /* horizontal fields of view, render and photo; 0: not given */
	int grid_w, grid_h;       /* the common grid; 0: the render's size */
	const char *side_path;    /* side-by-side PNG, or NULL */
	const char *overlay_path; /* split-screen or blend PNG, or NULL */
	const char *diff_path;    /* false-colour difference PNG, or NULL */
	double split;             /* overlay divider at this fraction of the width */
	double blend;             /* overlay: the photo's weight 0..1; < 0: split screen */
	double diff_range;        /* difference picture: levels at full colour */
	int (*progress)(void *user, double fraction); /* series: after each pair, or NULL */
	void *progress_user;
};

struct cs_skycompare_pair {
	long index;               /* series index, or -1 */
	char render[1024], photo[1024];
	int status;               /* CS_OK; 1: a file is missing (series); else an error */
	char message[512];        /* why, when status is not CS_OK */
	int render_w, render_h, photo_w, photo_h, grid_w, grid_h;
	int aspect_differs;       /* the photo window's aspect is not the grid's (> 2 %) */
	char render_sky[24], photo_sky[24]; /* how the sky was found: depth, auto, mask,
					     * horizon, all, depth+horizon */
	struct cs_sky_stats render_stats, photo_stats;
	struct cs_sky_diff diff;
	enum cs_verdict verdict;
	char verdict_text[256];
};

struct cs_skycompare_result {
	struct cs_skycompare_pair *pairs;
	int npairs;
	int compared, missing, failed;
	/* over the compared pairs */
	double mean_d_cloud, mean_abs_d_cloud; /* render - photo */
	double mean_emd, mean_lum_ratio;
	int verdicts[3];
};

/* Defaults: threshold CS_SKY_RB_THRESHOLD, exposure 0, automatic photo sky,
 * the render's grid, split at 0.5, diff range 32 levels, series from -1 to -1. */
void cs_skycompare_defaults(struct cs_skycompare_opts *o);

/* Compares the pair, or every pair of the series, and writes the pictures
 * (in a series, their names are patterns too).  Returns CS_EINVAL for
 * usage problems (a bad pattern, a crop outside the photo), the pair's
 * error for one pair; a series returns CS_OK with failed pairs recorded
 * (status and message) and CS_EDATA only when no pair was compared.
 * Free with cs_skycompare_result_free(), whatever it returned. */
int cs_skycompare_run(const struct cs_skycompare_opts *o, struct cs_skycompare_result *r);
void cs_skycompare_result_free(struct cs_skycompare_result *r);

/* The verdict of a comparison, and its one-line text (no newline). */
enum cs_verdict cs_skycompare_verdict(const struct cs_sky_stats *render,
				      const struct cs_sky_stats *photo,
				      const struct cs_sky_diff *d, char *text, size_t size);

/* Checks a series pattern: exactly one integer conversion %d, %Nd or %0Nd
 * (N < 10), %% for a percent sign.  CS_EINVAL (naming opt) otherwise. */
int cs_series_pattern_check(const char *opt, const char *pattern);

/* The pattern's name for index i, in buf. */
int cs_series_name(const char *pattern, long i, char *buf, size_t size);

#endif
