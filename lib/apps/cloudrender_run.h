/* cloudrender.h - the cloudrender program as a library call. */
#ifndef CS_CLOUDRENDER_H
#define CS_CLOUDRENDER_H

#include "render/render.h"
#include "weather/viewfile.h"
#include "weather/wx.h"

#include <signal.h>

#define CS_RENDER_MAX_OUTPUTS 4

struct cs_cloudrender_result;
struct cs_cloudrender_frame;
/* The formats of an output: chosen by the name's extension, or as GDAL's
 * -of names them. */
enum cs_out_format { CS_FMT_NONE, CS_FMT_PNG, CS_FMT_EXR, CS_FMT_TIFF, CS_FMT_JPEG };
#define CS_OUT_EXTENSIONS ".png, .exr, .tif, .tiff, .jpg or .jpeg"
#define CS_OUT_FORMAT_NAMES "PNG, EXR, GTiff (or TIFF) or JPEG (or JPG)"
/* Memory a frame takes per pixel, bytes: the float frame (R G B A Z),
 * the PNG and EXR encodings; measured as peak RSS growth between 400x200
 * and 1600x800 frames written to PNG and EXR (49 bytes a pixel). */
#define CS_CLOUDRENDER_BYTES_PER_PIXEL 49

struct cs_cloudrender_opts {
	const char *wx_path;      /* cloudwx JSON or "-", or NULL: built-in */
	const char *noise_path;   /* noise volume, or NULL: baked in memory */
	const char *terrain_path; /* heightfield from terrainprep, or NULL: flat */
	const char *terrain_color_path; /* PNG draped over the terrain, or NULL */
	const char *terrain_cpt_path;   /* GMT CPT palette for the terrain, or NULL */
	int noise_size;           /* in-memory bake size (default 64) */
	int have_time;
	double time_utc;          /* overrides the weather state's time */
	const char *view;         /* named viewpoint, or NULL */
	int have_camera;          /* explicit position */
	double cam_lat_deg, cam_lon_deg, cam_alt_m;
	int have_look;
	double look_az_deg, look_el_deg;
	double fov_deg;           /* 0: the view's, or 70 */
	/* easier cameras (cloudrender --camera-agl, --look-at, --views) */
	const struct cs_viewset *views; /* a --views file's, or NULL: built-in only */
	int have_camera_agl;      /* the camera camera_agl_m above the terrain (or
				   * the ground without terrain), whatever the
				   * view's or --camera's altitude */
	double camera_agl_m;
	int have_look_at;         /* look at this point instead of azimuth and
				   * elevation (excludes have_look) */
	double look_at_lat_deg, look_at_lon_deg, look_at_alt_m;
	enum cs_projection projection; /* perspective (default), fisheye, equirect */
	int irradiance;           /* measure the ground irradiance (--stats) */
	int width, height;
	struct cs_render_settings settings; /* the quality preset */
	/* explicit settings that refine the preset: 0 (seed -1) keeps the
	 * preset's; more steps raise max_steps to at least 4 x steps */
	int steps, light_steps, ms_octaves;
	int haze_steps;           /* -1 keeps the preset's */
	int max_steps;            /* 0 keeps the preset's (or 4 x steps) */
	double min_transmittance; /* < 0 keeps the preset's */
	int march, light_march;   /* -1 keep the preset's (CS_MARCH_*, CS_LIGHT_*) */
	int source_every;         /* 0 keeps the preset's; 1 or 2 */
	double tower_cell_m;      /* < 0 keeps the preset's; 0: none */
	int heap_towers;          /* < 0 keeps the preset's; 0 off, 1 on */
	int deck_lattice;         /* < 0 keeps the preset's; else CS_DECK_* */
	int ground_sky;           /* < 0 keeps the preset's; CS_GROUND_SKY_* */
	int no_ambient, no_jitter;
	long long seed;
	/* the reference integrator (render/reference.h) instead of the march:
	 * spp paths per pixel, max_bounces (0: unlimited) */
	int reference, spp, max_bounces;
	int no_haze;              /* no aerosol haze (fog stays) */
	enum cs_sky_level sky_level; /* the sky's absolute level (--sky-level) */
	int cloud_depth_genus;    /* the genera's optical depths: each state
				     read without the forecast's radiation,
				     which cs_scene_fit_beam would fit to */
	const char *quality;      /* the preset name, for reports */
	double exposure_ev;
	int exposure_auto;        /* choose exposure_ev from the image */
	int threads;
	const char *outputs[CS_RENDER_MAX_OUTPUTS]; /* files, "-" = standard output */
	enum cs_out_format formats[CS_RENDER_MAX_OUTPUTS]; /* NONE: from the name */
	int noutputs;
	int png16;                /* PNG: 16 bits a sample instead of 8 */
	int use_float;            /* EXR: float RGBA instead of half; TIFF: float
				   * linear R G B A Z instead of 16-bit sRGB */
	int jpeg_quality;         /* 1..100; 0: 90 */
	int no_clobber;           /* never replace an existing file */
	cs_progress_fn progress;
	void *progress_user;
	/* The caller's cancel flag (a signal handler's), or NULL: once set, the
	 * render in progress stops (CS_ECANCELED) and no further frame starts;
	 * an output being written is finished first, so no file is partial
	 * and no temporary is left. */
	const volatile sig_atomic_t *cancel;
	/* Called once the scene and camera are set, before the frame is
	 * rendered, with the result so far (for cloudrender -v), or NULL. */
	void (*ready)(void *user, const struct cs_cloudrender_result *r);
	void *ready_user;
	/* A series (cloudrender(1), SERIES): every state of wx_path is a
	 * frame, numbered start_number + its index (0 for the first state),
	 * and each output name is a pattern for that number
	 * (core/framename.h).  A single state with a literal name is the one
	 * frame it always was. */
	long long start_number;   /* >= 0; default 0 */
	long long frames_from;    /* the frames rendered: from <= number < to; */
	long long frames_to;      /* -1: from the first, to the last */
	int skip_existing;        /* an output that exists is not written again,
				   * a frame whose outputs all exist not rendered */
	int caption;              /* stamp the time and the weather in a corner */
	/* Called as each frame of a run starts, ends or is skipped (for the
	 * progress label, reports, --stats), or NULL.  The progress callback
	 * gets the fraction of the whole run, not of the frame. */
	void (*frame)(void *user, const struct cs_cloudrender_frame *f,
		      const struct cs_cloudrender_result *r);
	void *frame_user;
	/* The GPU renderer (render/device.h): CS_DEVICE_CPU (default) or
	 * CS_DEVICE_CUDA; device_bench > 0 renders the frame that many more
	 * times on the GPU, warm, timed by CUDA events (result.device_frame_ms). */
	int device;
	int device_bench;
};

/* A frame of a run, as the frame callback sees it. */
enum cs_frame_stage { CS_FRAME_START, CS_FRAME_DONE, CS_FRAME_SKIPPED };
struct cs_cloudrender_frame {
	enum cs_frame_stage stage;
	int index;                /* the state's index in the series, 0.. */
	long long number;         /* the number in its names */
	int states;               /* states in the series */
	int nth, count;           /* the nth (1..) of the count frames to render
				   * (skipped frames not counted) */
	int noutputs;             /* the outputs written (skip_existing: the missing) */
	char outputs[CS_RENDER_MAX_OUTPUTS][4096];
	double wall_s;            /* CS_FRAME_DONE: seconds the frame took */
};

/* What a run produced, for the program's report (--stats, warnings). */
struct cs_cloudrender_result {
	struct cs_render_settings settings; /* as rendered */
	double exposure_ev;       /* as applied to PNG outputs */
	struct cs_render_stats stats;
	double t_noise_s, t_scene_s, t_render_s, t_write_s;
	struct cs_wx wx;
	struct cs_scene *scene;   /* valid until cs_cloudrender_result_free() */
	double sun_azimuth_deg, sun_elevation_deg;
	double camera_site_km;    /* from the camera to the weather site */
	/* the camera as placed */
	double cam_lat_deg, cam_lon_deg, cam_alt_m;
	double look_az_deg, look_el_deg, fov_deg;
	char look_why[160];       /* "view gurten", "--look", or the default
				     view's reason (cs_default_look) */
	double camera_terrain_km; /* to the terrain's centre (-1 without terrain) */
	/* with opts.irradiance: at the camera, and the mean over a square of
	 * area_size_m around the weather site (a forecast's grid cell) */
	struct cs_irradiance irr_camera, irr_area;
	double area_size_m;
	double t_irradiance_s;
	/* fisheye only: the sky imager's cloud fraction of the rendered sky
	 * (red/blue ratio, io/skyclass.h; -1 otherwise), and the fraction of
	 * the same pixels whose clouds are more than half opaque */
	double cloud_fraction_rb, cloud_fraction_alpha;
	/* the reference integrator only: the relative standard error of the
	 * pixels' mean luminance, median and 95th percentile over the pixels
	 * with light (-1 otherwise) */
	double ref_rse_median, ref_rse_p95;
	/* --device cuda: the device, the kernel's time of the frame, and with
	 * device_bench the mean time of one warm frame (ms, CUDA events) */
	char device_name[160];
	double device_kernel_ms, device_frame_ms;
	const char *device_kernel; /* its name (cs_cuda_kernel_name) */
};

/* Defaults: built-in weather, in-memory noise, the default camera at the
 * weather site, 640x360, quality "medium", exposure 0, all threads. */
void cs_cloudrender_defaults(struct cs_cloudrender_opts *o);

/* The render settings a run uses: the preset refined by the explicit
 * settings. */
void cs_cloudrender_settings(const struct cs_cloudrender_opts *o,
			     struct cs_render_settings *s);

/* Renders and writes every output.  Usage-type problems (a bad size, an
 * unknown view, an output of unknown type, two outputs or inputs on the
 * standard streams) return CS_EINVAL; data problems CS_EDATA or CS_EIO.
 * Call cs_cloudrender_result_free() afterwards, whatever it returned. */
int cs_cloudrender_run(const struct cs_cloudrender_opts *o,
		       struct cs_cloudrender_result *r);
void cs_cloudrender_result_free(struct cs_cloudrender_result *r);

/* The frame's description (version, time, camera, quality and settings,
 * the weather's essentials) as one JSON object, written into PNG text and
 * EXR attributes; *json malloc'ed for the caller.  CS_ENOMEM. */
int cs_cloudrender_meta_json(const struct cs_cloudrender_opts *o,
			     const struct cs_cloudrender_result *r, char **json);
/* The caption of a frame (--caption): the time, the site, the layers and
 * the weather, lines separated by '\n', into buf. */
void cs_cloudrender_caption_text(const struct cs_cloudrender_result *r, char *buf,
				 size_t size);

/* The format a file name's extension means (.png, .exr, .tif, .tiff, .jpg,
 * .jpeg; any case); "-" is PNG; CS_FMT_NONE for any other. */
enum cs_out_format cs_output_format(const char *path);

/* The format GDAL's -of name means: PNG, EXR, GTiff or TIFF or TIF, JPEG or
 * JPG (any case); CS_FMT_NONE for any other. */
enum cs_out_format cs_output_format_named(const char *name);

/* The format output i is written in: as given, else from its name. */
enum cs_out_format cs_output_format_of(const struct cs_cloudrender_opts *o, int i);

#endif
