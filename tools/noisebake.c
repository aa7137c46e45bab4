/* noisebake - bake the seamless 3D noise volume the clouds are made of. */
#include "cli.h"

#include "core/err.h"
#include "core/info.h"
#include "apps/noisebake_run.h"
#include "noise/volume.h"

#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

#ifndef CS_VERSION
#define CS_VERSION "unknown"
#endif

static void usage(void)
{
	printf("Usage: noisebake [options] -o FILE.exr\n"
	       "       noisebake --info FILE.exr\n"
	       "Bake a tileable 3D noise volume (R: Perlin-Worley base shape;\n"
	       "G, B, A: Worley fBm detail) as an OpenEXR slice atlas.\n"
	       "\n"
	       "  -o, --output FILE      volume to write ('-' = standard output)\n"
	       "      --no-clobber       never replace an existing file (default: replace it,\n"
	       "                         whole, once the run has succeeded)\n"
	       "  -s, --size N           width and height in voxels, 2..1024 (default 128)\n"
	       "  -d, --depth D          depth in voxels, 1..1024 (default: the size)\n"
	       "      --seed S           random seed, 0..2147483647 (default 0)\n"
	       "      --freq R,G,B,A     lattice cells across the volume per channel,\n"
	       "                         1..256 (default 4,4,8,16)\n"
	       "      --octaves R,G,B,A  fBm octaves per channel, 1..12 (default 4,3,3,3)\n"
	       "      --worley-octaves N octaves of the Worley fBm inside R, 1..12 (default 3)\n"
	       "      --gain G           fBm amplitude ratio per octave, (0,1] (default 0.5)\n"
	       "      --float            32-bit float channels (default: half)\n"
	       "  -t, --threads N        worker threads, 1..256, also compressing an EXR\n"
	       "                         output (default: all processors)\n"
	       "      --preview FILE.png contact sheet: channels as rows, slices as columns\n"
	       "      --slices LIST      slices shown in the preview (default: 4 evenly spaced)\n"
	       "      --channels LETTERS channels shown in the preview (default RGBA)\n"
	       "      --info FILE        validate a volume and print its attributes and\n"
	       "                         per-channel statistics (as terrainprep --info)\n"
	       "      --json             --info as one JSON object\n"
	       "  -q, --quiet            no progress bar\n"
	       "  -v, --verbose          report the bake time and rate on stderr\n"
	       "  -h, --help             this help\n"
	       "      --version          print the version\n"
	       "\n"
	       "Exit status: 0 success, 1 data or runtime error, 2 usage error.\n"
	       "See noisebake(1) and cloudscape-noise(5).\n");
}

static int info(const char *path, int json)
{
	struct cs_volume v;
	if (cs_volume_read_exr(path, &v, 0) != CS_OK) {
		cli_err("%s", cs_errmsg());
		return EXIT_DATA;
	}
	char recipe[512];
	cs_noise_recipe_format(&v.recipe, recipe, sizeof recipe);
	struct cs_info in;
	cs_info_init(&in, json);
	cs_info_str(&in, "file", "file", path);
	const double size[3] = {v.nx, v.ny, v.nz};
	cs_info_nums(&in, "size", "size", size, 3, 0, " x ", NULL);
	cs_info_num(&in, "seed", "seed", v.recipe.seed, 0, NULL);
	cs_info_str(&in, "recipe", "recipe", recipe);
	static const char *const names[4] = {"R", "G", "B", "A"};
	cs_info_open(&in, "channels", "channels");
	for (int c = 0; c < 4; c++) {
		int p[3];
		double lo, hi, mean;
		cs_noise_period(&v.recipe, c, v.nx, v.nz, p);
		cs_volume_channel_stats(&v, c, &lo, &hi, &mean);
		const double period[3] = {p[0], p[1], p[2]};
		cs_info_open(&in, names[c], names[c]);
		cs_info_nums(&in, "period_cells", "period", period, 3, 0, " x ", "cells");
		cs_info_num(&in, "min", "min", lo, 4, NULL);
		cs_info_num(&in, "max", "max", hi, 4, NULL);
		cs_info_num(&in, "mean", "mean", mean, 4, NULL);
		cs_info_close(&in);
	}
	cs_volume_free(&v);
	return cli_info_print(&in);
}

/* Whether an output name fits its format: "-", an existing device or pipe
 * (/dev/stdout), or a name ending in ext. */
static int named_as(const char *path, const char *ext)
{
	struct stat st;
	size_t n = strlen(path), e = strlen(ext);
	if (strcmp(path, "-") == 0 || (stat(path, &st) == 0 && !S_ISREG(st.st_mode)))
		return 1;
	return n > e && strcasecmp(path + n - e, ext) == 0;
}

enum {
	OPT_SEED = 256, OPT_FREQ, OPT_OCTAVES, OPT_WORLEY_OCTAVES, OPT_GAIN,
	OPT_FLOAT, OPT_PREVIEW, OPT_SLICES, OPT_CHANNELS, OPT_INFO, OPT_JSON, OPT_NO_CLOBBER,
	OPT_VERSION,
};

int main(int argc, char **argv)
{
	static const struct option longopts[] = {
		{"output", required_argument, NULL, 'o'},
		{"no-clobber", no_argument, NULL, OPT_NO_CLOBBER},
		{"size", required_argument, NULL, 's'},
		{"depth", required_argument, NULL, 'd'},
		{"seed", required_argument, NULL, OPT_SEED},
		{"freq", required_argument, NULL, OPT_FREQ},
		{"octaves", required_argument, NULL, OPT_OCTAVES},
		{"worley-octaves", required_argument, NULL, OPT_WORLEY_OCTAVES},
		{"gain", required_argument, NULL, OPT_GAIN},
		{"float", no_argument, NULL, OPT_FLOAT},
		{"threads", required_argument, NULL, 't'},
		{"preview", required_argument, NULL, OPT_PREVIEW},
		{"slices", required_argument, NULL, OPT_SLICES},
		{"channels", required_argument, NULL, OPT_CHANNELS},
		{"info", required_argument, NULL, OPT_INFO},
		{"json", no_argument, NULL, OPT_JSON},
		{"quiet", no_argument, NULL, 'q'},
		{"verbose", no_argument, NULL, 'v'},
		{"help", no_argument, NULL, 'h'},
		{"version", no_argument, NULL, OPT_VERSION},
		{NULL, 0, NULL, 0},
	};
	struct cs_noisebake_opts o;
	const char *info_path = NULL;
	int json = 0;
	const char *slices_arg = NULL;
	int opt, output_given = 0;

	cli_init("noisebake");
	cs_noisebake_defaults(&o);
	while ((opt = getopt_long(argc, argv, "o:s:d:t:qvh", longopts, NULL)) != -1) {
		switch (opt) {
		case 'o':
			o.output = cli_one_output(&output_given, optarg);
			break;
		case OPT_NO_CLOBBER: o.no_clobber = 1; break;
		case 's': o.size = (int)cli_long("--size", optarg, 2, CS_VOLUME_MAX_DIM); break;
		case 'd': o.depth = (int)cli_long("--depth", optarg, 1, CS_VOLUME_MAX_DIM); break;
		case OPT_SEED: o.recipe.seed = (uint32_t)cli_long("--seed", optarg, 0, 2147483647L); break;
		case OPT_FREQ: cli_long_list("--freq", optarg, 1, 256, 4, o.recipe.freq); break;
		case OPT_OCTAVES: cli_long_list("--octaves", optarg, 1, 12, 4, o.recipe.octaves); break;
		case OPT_WORLEY_OCTAVES:
			o.recipe.worley_octaves = (int)cli_long("--worley-octaves", optarg, 1, 12);
			break;
		case OPT_GAIN:
			o.recipe.gain = cli_double("--gain", optarg, 1e-6, 1.0);
			break;
		case OPT_FLOAT: o.use_float = 1; break;
		case 't': o.threads = (int)cli_long("--threads", optarg, 1, 256); break;
		case OPT_PREVIEW: o.preview = optarg; break;
		case OPT_SLICES: slices_arg = optarg; break;
		case OPT_CHANNELS:
			if (optarg[0] == '\0' || strlen(optarg) > 4 ||
			    strspn(optarg, "RGBA") != strlen(optarg))
				cli_usage_error("--channels: '%s' must be 1 to 4 letters of RGBA", optarg);
			strcpy(o.channels, optarg);
			break;
		case OPT_INFO: info_path = optarg; break;
		case OPT_JSON: json = 1; break;
		case 'q': cli_quiet = 1; break;
		case 'v': cli_verbose = 1; break;
		case 'h': usage(); return EXIT_OK;
		case OPT_VERSION: printf("noisebake (cloudscape) %s\n", CS_VERSION); return EXIT_OK;
		default:
			fprintf(stderr, "Try 'noisebake --help' for more information.\n");
			return EXIT_USAGE;
		}
	}
	if (optind < argc)
		cli_usage_error("unexpected argument '%s'", argv[optind]);
	if (info_path) {
		if (o.output || o.preview)
			cli_usage_error("--info reads a volume; it cannot be combined with -o or --preview");
		return info(info_path, json);
	}
	if (json)
		cli_usage_error("--json goes with --info");
	if (o.output == NULL && o.preview == NULL)
		cli_usage_error("no output: give -o FILE.exr and/or --preview FILE.png");
	if (o.output && !named_as(o.output, ".exr"))
		cli_usage_error("-o %s: the volume is OpenEXR: name it .exr (or '-')", o.output);
	if (o.preview && !named_as(o.preview, ".png"))
		cli_usage_error("--preview %s: the preview is a PNG: name it .png (or '-')", o.preview);
	if (o.output && o.preview && strcmp(o.output, "-") == 0 && strcmp(o.preview, "-") == 0)
		cli_usage_error("-o - and --preview - cannot both use standard output");
	int depth = o.depth > 0 ? o.depth : o.size;
	if (slices_arg) {
		char buf[1024];
		if (strlen(slices_arg) >= sizeof buf)
			cli_usage_error("--slices: list too long");
		strcpy(buf, slices_arg);
		char *save = NULL;
		for (char *t = strtok_r(buf, ",", &save); t; t = strtok_r(NULL, ",", &save)) {
			if (o.nslices == CS_PREVIEW_MAX_SLICES)
				cli_usage_error("--slices: at most %d slices", CS_PREVIEW_MAX_SLICES);
			o.slices[o.nslices++] = (int)cli_long("--slices", t, 0, depth - 1);
		}
		if (o.nslices == 0)
			cli_usage_error("--slices: empty list");
	}
	if (o.recipe.gain <= 0.0)
		cli_usage_error("--gain must be above 0");

	o.progress = cli_progress;
	o.progress_user = "baking";
	struct cs_noisebake_result r;
	int rc = cs_noisebake_run(&o, &r);
	cli_progress_done();
	if (rc != CS_OK) {
		cli_err("%s", cs_errmsg());
		return rc == CS_EINVAL ? EXIT_USAGE : EXIT_DATA;
	}
	if (cli_verbose) {
		double voxels = (double)r.nx * r.ny * r.nz;
		fprintf(stderr,
			"noisebake: baked %dx%dx%d (%.0f voxels) in %.3f s: %.3f Mvoxel/s\n",
			r.nx, r.ny, r.nz, voxels, r.bake_seconds,
			voxels / r.bake_seconds / 1e6);
	}
	return EXIT_OK;
}
