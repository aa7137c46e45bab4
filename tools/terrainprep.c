/* terrainprep - any DEM GDAL reads to a metric heightfield for cloudrender. */
#include "cli.h"

#include "core/err.h"
#include "apps/terrainprep_run.h"

#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#ifndef CS_VERSION
#define CS_VERSION "unknown"
#endif

static void usage(void)
{
	printf("Usage: terrainprep [options] -o FILE DEM...\n"
	       "Turn elevation data GDAL reads (GeoTIFF, SRTM .hgt, DTED, ESRI .asc, XYZ;\n"
	       "several tiles are mosaicked; '-' reads standard input) into a metric,\n"
	       "north-up heightfield with a JSON sidecar (FILE with .json).\n"
	       "\n"
	       "  -o, --output FILE        heightfield to write (.exr; .tif or .r16 choose\n"
	       "                           the format unless --format says otherwise;\n"
	       "                           another extension such as .png is refused)\n"
	       "      --no-clobber         never replace an existing file (default: replace\n"
	       "                           it, whole, once the run has succeeded)\n"
	       "  -f, --format FMT         exr (32-bit float), r16 (16-bit raw, little-endian,\n"
	       "                           min..max scaled to 0..65535) or tif (Float32 GeoTIFF)\n"
	       "      --stdin-name NAME    file name '-' is opened under (e.g. N46E007.hgt:\n"
	       "                           some drivers take the position from it)\n"
	       "      --s-srs SRS          CRS of the input (required when it has none)\n"
	       "      --t-srs SRS          output CRS, projected in metres (default: the\n"
	       "                           input's if metric, else the UTM zone of the centre)\n"
	       "      --center LAT,LON     crop a square around this point (degrees) ...\n"
	       "      --radius KM          ... reaching KM km from it on each side\n"
	       "      --bounds X0,Y0,X1,Y1 crop to these bounds (output CRS or --bounds-srs)\n"
	       "      --bounds-srs SRS     CRS the bounds are given in\n"
	       "      --res M              pixel size in metres\n"
	       "      --size N|WxH|unity   N samples along the longer side, exactly WxH, or\n"
	       "                           the square 2^n+1 (33..4097) Unity terrain wants\n"
	       "  -r, --resampling ALG     near, bilinear, cubic, cubicspline, lanczos, average,\n"
	       "                           rms, mode, max, min, med, q1, q3, sum (default:\n"
	       "                           bilinear; average when shrinking more than 2x)\n"
	       "      --src-nodata V|none  the input's void value (default: the file's)\n"
	       "      --fill MODE          voids: nearest (default), value[=V] (V default 0)\n"
	       "                           or none (kept as NaN; exr and tif only)\n"
	       "      --max-void-fraction F  more voids than F (0..1, default 0.5) is an error\n"
	       "      --flip               r16: south row first (for importers that flip)\n"
	       "      --hillshade FILE.png grey hillshade of the result (as gdaldem's)\n"
	       "      --azimuth DEG        sun azimuth, clockwise from north (default 315)\n"
	       "      --altitude DEG       sun altitude (default 45)\n"
	       "      --z-factor Z         vertical exaggeration (default 1)\n"
	       "      --scale S            horizontal units per vertical unit (default 1)\n"
	       "      --water-level M      samples at or below M metres are water\n"
	       "      --water-mask FILE    raster GDAL reads (e.g. a lake rasterised with\n"
	       "                           gdal_rasterize): non-zero, non-nodata is water\n"
	       "      --info FILE.exr      describe a heightfield: size, CRS, pixel size in\n"
	       "                           CRS units and on the ground, WGS84 bounds,\n"
	       "                           min/max/mean height, voids, water\n"
	       "      --json               --info as one JSON object\n"
	       "  -q, --quiet              no progress bar, no warnings\n"
	       "  -v, --verbose            describe the result on stderr\n"
	       "  -h, --help               this help\n"
	       "      --version            print the version\n"
	       "\n"
	       "Exit status: 0 success, 1 data or runtime error, 2 usage error.\n"
	       "See terrainprep(1).\n");
}

static void parse_size(const char *s, struct cs_terrainprep_opts *o)
{
	const char *x = strchr(s, 'x');
	if (strcasecmp(s, "unity") == 0) {
		o->size_unity = 1;
	} else if (x) {
		char w[32];
		if ((size_t)(x - s) >= sizeof w)
			cli_usage_error("--size: '%s' is not N, WxH or unity", s);
		memcpy(w, s, (size_t)(x - s));
		w[x - s] = '\0';
		o->size_w = (int)cli_long("--size", w, 2, 65536);
		o->size_h = (int)cli_long("--size", x + 1, 2, 65536);
	} else {
		o->size_long = (int)cli_long("--size", s, 2, 65536);
	}
}

static void parse_fill(const char *s, struct cs_terrainprep_opts *o)
{
	if (strcasecmp(s, "nearest") == 0) {
		o->fill = CS_FILL_NEAREST;
	} else if (strcasecmp(s, "none") == 0) {
		o->fill = CS_FILL_NONE;
	} else if (strcasecmp(s, "value") == 0) {
		o->fill = CS_FILL_VALUE;
		o->fill_value = 0.0;
	} else if (strncasecmp(s, "value=", 6) == 0) {
		o->fill = CS_FILL_VALUE;
		o->fill_value = cli_double("--fill", s + 6, -1e6, 1e6);
	} else {
		cli_usage_error("--fill: '%s' is not nearest, none, value or value=V", s);
	}
}

static int format_of(const char *name)
{
	enum cs_terrain_format f;
	if (cs_terrainprep_format(name, &f) != CS_OK)
		cli_usage_error("--format: %s", cs_errmsg());
	return (int)f;
}

static void describe(const struct cs_terrainprep_opts *o, const struct cs_terrainprep_result *r)
{
	const struct cs_terrain *t = &r->terrain;
	double n = (double)t->width * t->height;
	fprintf(stderr, "terrainprep: %dx%d samples of %gx%g m, EPSG:%d, heights %g..%g m, "
		"resampling %s, %ld voids (%.2f%%)%s\n",
		t->width, t->height, t->pixel_x_m, t->pixel_y_m, t->epsg, t->min_m, t->max_m,
		r->resampling_used, r->voids, 100.0 * (double)r->voids / n,
		r->voids == 0 ? "" : o->fill == CS_FILL_NONE ? " kept" : " filled");
	fprintf(stderr, "terrainprep: centre %.6f, %.6f (WGS84)\n", t->center_lat, t->center_lon);
	if (t->water)
		fprintf(stderr, "terrainprep: %ld water samples (%.2f%%)\n", cs_terrain_water_count(t),
			100.0 * (double)cs_terrain_water_count(t) / n);
}

/* GDAL's warnings and ours, one a line, unless -q. */
static void warn(const struct cs_terrainprep_result *r)
{
	if (cli_quiet)
		return;
	for (const char *p = r->warning; *p;) {
		size_t n = strcspn(p, "\n");
		cli_err("warning: %.*s", (int)n, p);
		p += n + (p[n] == '\n');
	}
}

enum {
	OPT_STDIN_NAME = 256, OPT_S_SRS, OPT_T_SRS, OPT_CENTER, OPT_RADIUS, OPT_BOUNDS,
	OPT_BOUNDS_SRS, OPT_RES, OPT_SIZE, OPT_SRC_NODATA, OPT_FILL, OPT_MAX_VOID, OPT_FLIP,
	OPT_HILLSHADE, OPT_AZIMUTH, OPT_ALTITUDE, OPT_Z_FACTOR, OPT_SCALE, OPT_NO_CLOBBER, OPT_VERSION,
	OPT_WATER_LEVEL, OPT_WATER_MASK, OPT_INFO, OPT_JSON,
};

int main(int argc, char **argv)
{
	static const struct option longopts[] = {
		{"output", required_argument, NULL, 'o'},
		{"no-clobber", no_argument, NULL, OPT_NO_CLOBBER},
		{"format", required_argument, NULL, 'f'},
		{"stdin-name", required_argument, NULL, OPT_STDIN_NAME},
		{"s-srs", required_argument, NULL, OPT_S_SRS},
		{"t-srs", required_argument, NULL, OPT_T_SRS},
		{"center", required_argument, NULL, OPT_CENTER},
		{"radius", required_argument, NULL, OPT_RADIUS},
		{"bounds", required_argument, NULL, OPT_BOUNDS},
		{"bounds-srs", required_argument, NULL, OPT_BOUNDS_SRS},
		{"res", required_argument, NULL, OPT_RES},
		{"size", required_argument, NULL, OPT_SIZE},
		{"resampling", required_argument, NULL, 'r'},
		{"src-nodata", required_argument, NULL, OPT_SRC_NODATA},
		{"fill", required_argument, NULL, OPT_FILL},
		{"max-void-fraction", required_argument, NULL, OPT_MAX_VOID},
		{"flip", no_argument, NULL, OPT_FLIP},
		{"hillshade", required_argument, NULL, OPT_HILLSHADE},
		{"azimuth", required_argument, NULL, OPT_AZIMUTH},
		{"altitude", required_argument, NULL, OPT_ALTITUDE},
		{"z-factor", required_argument, NULL, OPT_Z_FACTOR},
		{"scale", required_argument, NULL, OPT_SCALE},
		{"water-level", required_argument, NULL, OPT_WATER_LEVEL},
		{"water-mask", required_argument, NULL, OPT_WATER_MASK},
		{"info", required_argument, NULL, OPT_INFO},
		{"json", no_argument, NULL, OPT_JSON},
		{"quiet", no_argument, NULL, 'q'},
		{"verbose", no_argument, NULL, 'v'},
		{"help", no_argument, NULL, 'h'},
		{"version", no_argument, NULL, OPT_VERSION},
		{NULL, 0, NULL, 0},
	};
	struct cs_terrainprep_opts o;
	int have_radius = 0, json = 0;
	const char *info_path = NULL;
	double ll[2];
	int opt, output_given = 0;

	cli_init("terrainprep");
	cs_terrainprep_defaults(&o);
	while ((opt = getopt_long(argc, argv, "o:f:r:qvh", longopts, NULL)) != -1) {
		switch (opt) {
		case 'o':
			o.output = cli_one_output(&output_given, optarg);
			break;
		case OPT_NO_CLOBBER: o.no_clobber = 1; break;
		case 'f': o.format = format_of(optarg); break;
		case OPT_STDIN_NAME: o.stdin_name = optarg; break;
		case OPT_S_SRS: o.s_srs = optarg; break;
		case OPT_T_SRS: o.t_srs = optarg; break;
		case OPT_CENTER:
			cli_double_list("--center", optarg, -180.0, 180.0, 2, ll);
			if (ll[0] < -90.0 || ll[0] > 90.0)
				cli_usage_error("--center: latitude %g is out of range -90..90", ll[0]);
			o.have_center = 1;
			o.center_lat = ll[0];
			o.center_lon = ll[1];
			break;
		case OPT_RADIUS:
			o.radius_km = cli_double("--radius", optarg, 0.001, 5000.0);
			have_radius = 1;
			break;
		case OPT_BOUNDS:
			cli_double_list("--bounds", optarg, -1e9, 1e9, 4, o.bounds);
			o.have_bounds = 1;
			break;
		case OPT_BOUNDS_SRS: o.bounds_srs = optarg; break;
		case OPT_RES: o.res_m = cli_double("--res", optarg, 0.001, 1e6); break;
		case OPT_SIZE: parse_size(optarg, &o); break;
		case 'r': o.resampling = optarg; break;
		case OPT_SRC_NODATA:
			o.have_src_nodata = 1;
			o.src_nodata_none = strcasecmp(optarg, "none") == 0;
			if (!o.src_nodata_none)
				o.src_nodata = cli_double("--src-nodata", optarg, -1e38, 1e38);
			break;
		case OPT_FILL: parse_fill(optarg, &o); break;
		case OPT_MAX_VOID:
			o.max_void_fraction = cli_double("--max-void-fraction", optarg, 0.0, 1.0);
			break;
		case OPT_FLIP: o.r16_south_up = 1; break;
		case OPT_HILLSHADE: o.hillshade = optarg; break;
		case OPT_AZIMUTH: o.azimuth_deg = cli_double("--azimuth", optarg, 0.0, 360.0); break;
		case OPT_ALTITUDE: o.altitude_deg = cli_double("--altitude", optarg, 0.0, 90.0); break;
		case OPT_Z_FACTOR: o.z_factor = cli_double("--z-factor", optarg, 1e-6, 1e6); break;
		case OPT_SCALE: o.scale = cli_double("--scale", optarg, 1e-6, 1e9); break;
		case OPT_WATER_LEVEL:
			o.water_level_m = cli_double("--water-level", optarg, -12000.0, 9000.0);
			o.have_water_level = 1;
			break;
		case OPT_WATER_MASK: o.water_mask = optarg; break;
		case OPT_INFO: info_path = optarg; break;
		case OPT_JSON: json = 1; break;
		case 'q': cli_quiet = 1; break;
		case 'v': cli_verbose = 1; break;
		case 'h': usage(); return EXIT_OK;
		case OPT_VERSION: printf("terrainprep (cloudscape) %s\n", CS_VERSION); return EXIT_OK;
		default:
			fprintf(stderr, "Try 'terrainprep --help' for more information.\n");
			return EXIT_USAGE;
		}
	}
	if (info_path) {
		if (optind < argc || o.output || o.hillshade)
			cli_usage_error("--info reads a heightfield: no DEM, -o or --hillshade with it");
		char *text = NULL;
		if (cs_terrainprep_info(info_path, json, &text) != CS_OK) {
			cli_err("%s", cs_errmsg());
			return EXIT_DATA;
		}
		fputs(text, stdout);
		free(text);
		return fflush(stdout) == 0 ? EXIT_OK : EXIT_DATA;
	}
	if (json)
		cli_usage_error("--json goes with --info");
	o.inputs = (const char **)(argv + optind);
	o.ninputs = argc - optind;
	if (o.ninputs == 0)
		cli_usage_error("no input DEM (give a file, or '-' for standard input)");
	if (o.output == NULL && o.hillshade == NULL)
		cli_usage_error("no output: give -o FILE and/or --hillshade FILE.png");
	if (o.output && strcmp(o.output, "-") == 0)
		cli_usage_error("-o: a heightfield is two files (data and sidecar): give a file name");
	if (o.have_center != have_radius)
		cli_usage_error("--center and --radius go together");

	o.progress = cli_progress;
	o.progress_user = "warping";
	struct cs_terrainprep_result r;
	int rc = cs_terrainprep_run(&o, &r);
	cli_progress_done();
	warn(&r);
	if (rc != CS_OK) {
		cli_err("%s", cs_errmsg());
		cs_terrainprep_result_free(&r);
		return rc == CS_EINVAL ? EXIT_USAGE : EXIT_DATA;
	}
	if (cli_verbose)
		describe(&o, &r);
	cs_terrainprep_result_free(&r);
	return EXIT_OK;
}
