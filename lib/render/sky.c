#include "render/sky.h"

#include "core/vec.h"

#include <math.h>

#define DEG (CS_PI / 180.0)
#define LN10 2.30258509299404568402

/* Sun angular radius (0.2666 deg) and limb darkening I(mu)/I(1) =
 * 1 - u (1 - mu), with the usual grey coefficient u = 0.6; the disk mean of
 * that profile is 1 - u/3. */
static const double SUN_RADIUS = 0.2666 * DEG;
static const double LIMB_U = 0.6;

/* Extraterrestrial solar illuminance 128 klux (the usual value, e.g. the
 * IES / Preetham daylight literature): the disk radiance outside the
 * atmosphere is that over the disk's solid angle, ~1.88e6 kcd/m².  Taken as
 * D65 white, the white point of our RGB. */
static const double SUN_E0 = 128.0;

/* The Perez fit is invalid for a sun below ~2 deg (Yz < 0 for high T), so
 * the shape is computed for a sun raised to 2 deg and dimmed below. */
static const double SHAPE_ELEV = 2.0 * DEG;

/* Rayleigh optical depth at 680 / 550 / 440 nm (R, G, B), aerosol
 * Angstrom exponent 1.3 relative to 550 nm. */
static CS_CONST const double TAU_R[3] = {0.0411, 0.0973, 0.2428};
static const double LAMBDA[3] = {680.0, 550.0, 440.0};

/* XYZ -> linear sRGB and its luminance row, from the Rec. 709 primaries and
 * D65 (0.3127, 0.3290) to full double precision (inverse of each other). */
static CS_CONST const double XYZ_TO_RGB[3][3] = {
	{3.2409699419045, -1.5373831775701, -0.4986107602930},
	{-0.9692436362809, 1.8759675015077, 0.0415550574072},
	{0.0556300796970, -0.2039769588890, 1.0569715142429},
};
static CS_CONST const double Y_ROW[3] = {0.2126390058715, 0.7151686787678,
				0.0721923153607};

CS_HD static double clampd(double v, double lo, double hi)
{
	return v < lo ? lo : v > hi ? hi : v;
}

/* Perez et al. (1993) all-weather distribution, Preetham eq. 3. */
CS_HD static double perez(const double c[5], double cos_theta, double gamma,
		    double cos_gamma)
{
	return (1.0 + c[0] * exp(c[1] / cos_theta)) *
	       (1.0 + c[2] * exp(c[3] * gamma) + c[4] * cos_gamma * cos_gamma);
}

/* xyY -> linear sRGB; negative (out of gamut) or NaN channels become 0. */
CS_HD static void xyY_to_rgb(double x, double y, double Y, double rgb[3])
{
	double xyz[3] = {x / y * Y, Y, (1.0 - x - y) / y * Y};
	for (int i = 0; i < 3; i++) {
		double v = XYZ_TO_RGB[i][0] * xyz[0] + XYZ_TO_RGB[i][1] * xyz[1] +
			   XYZ_TO_RGB[i][2] * xyz[2];
		rgb[i] = v > 0.0 ? v : 0.0;
	}
}

double cs_relative_air_mass(double elev)
{
	double z = CS_PI / 2 - (elev > 0.0 ? elev : 0.0);
	return 1.0 / (cos(z) + 0.50572 * pow(96.07995 - z / DEG, -1.6364));
}

/* Twilight dimming in decades for a sun d degrees below the 2 deg shape
 * elevation: quadratic onset (no kink at 2 deg), then 0.42 decades per
 * degree (one decade per ~2.4 deg, as measured twilight illuminance falls
 * between sunset and -12 deg).  With Yz(2 deg, T=2.5) = 2 kcd/m² the zenith
 * reads ~0.8 kcd/m² at sunset, ~4 cd/m² at -6 deg, ~0.015 cd/m² at -12 deg,
 * and sinks under the night floor near -15 deg. */
CS_HD static double twilight_decades(double d)
{
	return 0.42 * d * d / (d + 2.0);
}

double cs_turbidity_from_visibility(double visibility_m)
{
	if (!(visibility_m > 0.0))
		return 10.0;
	double tau_a = (3.912 / visibility_m - 1.16e-5) * 1200.0;
	return clampd(tau_a / CS_RAYLEIGH_DEPTH_550 + 1.0, 1.7, 10.0);
}

static void perez_coefficients(double T, double c[3][5])
{
	/* Preetham 1999, appendix A.2: each coefficient is linear in T. */
	static const double k[3][5][2] = {
		{{0.1787, -1.4630}, {-0.3554, 0.4275}, {-0.0227, 5.3251},
		 {0.1206, -2.5771}, {-0.0670, 0.3703}},
		{{-0.0193, -0.2592}, {-0.0665, 0.0008}, {-0.0004, 0.2125},
		 {-0.0641, -0.8989}, {-0.0033, 0.0452}},
		{{-0.0167, -0.2608}, {-0.0950, 0.0092}, {-0.0079, 0.2102},
		 {-0.0441, -1.6537}, {-0.0109, 0.0529}},
	};
	for (int i = 0; i < 3; i++)
		for (int j = 0; j < 5; j++)
			c[i][j] = k[i][j][0] * T + k[i][j][1];
}

/* Zenith luminance (kcd/m²) and chromaticity, Preetham appendix A.2. */
static void zenith_values(double T, double ts, double out[3])
{
	static const double mx[3][4] = {
		{0.00166, -0.00375, 0.00209, 0.0},
		{-0.02903, 0.06377, -0.03202, 0.00394},
		{0.11693, -0.21196, 0.06052, 0.25886},
	};
	static const double my[3][4] = {
		{0.00275, -0.00610, 0.00317, 0.0},
		{-0.04214, 0.08970, -0.04153, 0.00516},
		{0.15346, -0.26756, 0.06670, 0.26688},
	};
	double tv[4] = {ts * ts * ts, ts * ts, ts, 1.0};
	double Tv[3] = {T * T, T, 1.0};
	double chi = (4.0 / 9.0 - T / 120.0) * (CS_PI - 2.0 * ts);
	out[0] = (4.0453 * T - 4.9710) * tan(chi) - 0.2155 * T + 2.4192;
	out[1] = out[2] = 0.0;
	for (int i = 0; i < 3; i++)
		for (int j = 0; j < 4; j++) {
			out[1] += Tv[i] * mx[i][j] * tv[j];
			out[2] += Tv[i] * my[i][j] * tv[j];
		}
}

/* Fraction of the sun's light above the horizon, for the limb-darkened
 * profile on a flat disk: with the centre at u radii above the horizon, a
 * uniform disk shows (acos(-u) + u sqrt(1-u²)) / π of its area and the
 * mu-weighted part shows 1/2 + 3u/4 - u³/4 of its light. */
static double disk_fraction(double elev)
{
	double u = clampd(elev / SUN_RADIUS, -1.0, 1.0);
	double flat = (acos(-u) + u * sqrt(1.0 - u * u)) / CS_PI;
	double mu = 0.5 + 0.75 * u - 0.25 * u * u * u;
	return ((1.0 - LIMB_U) * flat + LIMB_U * (2.0 / 3.0) * mu) /
	       (1.0 - LIMB_U / 3.0);
}

static void init_sun(struct cs_sky *sky, double elev, double beam_turbidity)
{
	double omega = 2.0 * CS_PI * (1.0 - cos(SUN_RADIUS));
	double frac = disk_fraction(elev);
	double m = cs_relative_air_mass(elev);
	for (int i = 0; i < 3; i++) {
		double tau = TAU_R[i] + (beam_turbidity - 1.0) * CS_RAYLEIGH_DEPTH_550 *
						pow(LAMBDA[i] / 550.0, -1.3);
		double L = frac > 0.0 ? SUN_E0 / omega * exp(-tau * m) : 0.0;
		sky->sun_radiance[i] = L;
		sky->sun_illuminance[i] = L * omega * frac;
	}
	sky->cos_sun_radius = cos(SUN_RADIUS);
	sky->sin2_sun_radius = sin(SUN_RADIUS) * sin(SUN_RADIUS);
}

/* Cosine-weighted hemisphere mean: rings uniform in theta, each weighted
 * by its exact share of cos(theta) dω / π, (sin² θ1 - sin² θ0); the
 * midpoint radiance per cell.  Uniform theta (not sin² θ) resolves the
 * bright band near the horizon, within 1% of a fine quadrature even for
 * the twilight glow; 24 x 64 cells. */
static void init_ambient(struct cs_sky *sky, double elev)
{
	enum { NT = 24, NPHI = 64 };
	double sum[3] = {0.0, 0.0, 0.0};
	for (int i = 0; i < NT; i++) {
		double s0 = sin(i * (CS_PI / 2) / NT), s1 = sin((i + 1) * (CS_PI / 2) / NT);
		double th = (i + 0.5) * (CS_PI / 2) / NT, w = (s1 * s1 - s0 * s0) / NPHI;
		for (int j = 0; j < NPHI; j++) {
			double phi = (j + 0.5) * 2.0 * CS_PI / NPHI, rgb[3];
			cs_v3 d = v3(sin(th) * cos(phi), sin(th) * sin(phi), cos(th));
			cs_sky_radiance(sky, d, rgb);
			for (int c = 0; c < 3; c++)
				sum[c] += w * rgb[c];
		}
	}
	double sin_h = elev > 0.0 ? sin(elev) : 0.0;
	for (int c = 0; c < 3; c++) {
		sky->ambient_up[c] = sum[c];
		sky->ambient_down[c] =
			0.2 * (sky->sun_illuminance[c] * sin_h / CS_PI +
			       sky->ambient_up[c]);
	}
}

cs_v3 cs_sky_raise(cs_v3 d, double elevation_rad)
{
	if (asin(clampd(d.z, -1.0, 1.0)) >= elevation_rad)
		return d;
	double hx = d.x, hy = d.y, hl = sqrt(hx * hx + hy * hy);
	if (hl > 0.0)
		hx /= hl, hy /= hl;
	else
		hx = 1.0, hy = 0.0;
	return v3(cos(elevation_rad) * hx, cos(elevation_rad) * hy, sin(elevation_rad));
}

void cs_sky_scale_dome(struct cs_sky *sky, double f)
{
	if (!(f > 0.0) || !isfinite(f) || f == 1.0)
		return;
	sky->scale[0] *= f;
	init_ambient(sky, asin(clampd(sky->sun_dir.z, -1.0, 1.0)));
}

void cs_sky_init(struct cs_sky *sky, cs_v3 sun, double turbidity)
{
	cs_sky_init_beam(sky, sun, turbidity, turbidity);
}

void cs_sky_init_beam(struct cs_sky *sky, cs_v3 sun, double turbidity, double beam_turbidity)
{
	/* Scaled by the largest component first so huge ones don't overflow. */
	const double sun_dir[3] = {sun.x, sun.y, sun.z};
	double s[3], big = 0.0;
	for (int i = 0; i < 3; i++)
		big = fabs(sun_dir[i]) > big ? fabs(sun_dir[i]) : big;
	int ok = big > 0.0 && isfinite(big);
	for (int i = 0; i < 3; i++)
		s[i] = ok ? sun_dir[i] / big : i == 2;
	double n = sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
	if (!(n > 0.0)) /* a NaN component */
		s[0] = s[1] = 0.0, s[2] = n = 1.0;
	sky->sun_dir = v3(s[0] / n, s[1] / n, s[2] / n);
	double T = clampd(turbidity, 1.7, 10.0);
	sky->turbidity = T = isnan(T) ? 1.7 : T;

	double elev = asin(clampd(sky->sun_dir.z, -1.0, 1.0));
	double *sh = sky->shape_sun;
	cs_v3 raised = cs_sky_raise(sky->sun_dir, SHAPE_ELEV);
	sh[0] = raised.x, sh[1] = raised.y, sh[2] = raised.z;

	double ts = acos(clampd(sh[2], -1.0, 1.0)), zen[3];
	perez_coefficients(T, sky->perez);
	zenith_values(T, ts, zen);
	for (int i = 0; i < 3; i++)
		sky->scale[i] = zen[i] / perez(sky->perez[i], 1.0, ts, sh[2]);

	double d = elev < SHAPE_ELEV ? (SHAPE_ELEV - elev) / DEG : 0.0;
	sky->depression = d;
	sky->twilight = exp(-LN10 * twilight_decades(d));
	/* The warm tint grows over the first 4 deg of dimming (smoothstep). */
	double t = clampd(d / 4.0, 0.0, 1.0);
	sky->glow_tint = 3.0 * t * t * (3.0 - 2.0 * t);

	/* Moonless night: 1 mcd/m², bluish grey. */
	static const double night[3] = {0.80, 0.90, 1.15};
	double ny = Y_ROW[0] * night[0] + Y_ROW[1] * night[1] + Y_ROW[2] * night[2];
	for (int i = 0; i < 3; i++)
		sky->night[i] = 1e-6 * night[i] / ny;

	double Tb = clampd(beam_turbidity, 1.7, 10.0);
	init_sun(sky, elev, isnan(Tb) ? T : Tb);
	init_ambient(sky, elev);
}

CS_HD CS_COLD void cs_sky_radiance(const struct cs_sky *sky, cs_v3 dir, double rgb[3])
{
	double v[3] = {dir.x, dir.y, dir.z};
	if (v[2] < 0.0) {
		double hl = sqrt(v[0] * v[0] + v[1] * v[1]);
		if (hl > 0.0)
			v[0] /= hl, v[1] /= hl;
		else
			v[0] = 1.0, v[1] = 0.0;
		v[2] = 0.0;
	}
	/* cos(theta) >= 0.01 keeps exp(B / cos(theta)) finite at the horizon. */
	double cos_t = v[2] > 0.01 ? v[2] : 0.01;
	const double *sh = sky->shape_sun;
	double cos_g = clampd(v[0] * sh[0] + v[1] * sh[1] + v[2] * sh[2], -1.0, 1.0);
	double g = acos(cos_g);
	double Y = sky->scale[0] * perez(sky->perez[0], cos_t, g, cos_g);
	double x = sky->scale[1] * perez(sky->perez[1], cos_t, g, cos_g);
	double y = sky->scale[2] * perez(sky->perez[2], cos_t, g, cos_g);
	xyY_to_rgb(x, y > 1e-6 ? y : 1e-6, Y, rgb);
	if (sky->depression <= 0.0)
		return;

	/* Twilight: the sky toward the sun's azimuth near the horizon is lit
	 * by sunlight that grazes the atmosphere there, so it dims as if the
	 * sun were up to 3 deg higher, and is reddened by a Rayleigh-like
	 * transmittance (normalised to keep luminance); the night floor fills
	 * in what the day sky loses. */
	double a = 0.5 * (1.0 + cos_g);
	double w = a * a * exp(-v[2] / 0.17);
	double de = sky->depression - 3.0 * w;
	double f = exp(-LN10 * twilight_decades(de > 0.0 ? de : 0.0));
	double q[3], qy = 0.0;
	for (int i = 0; i < 3; i++) {
		q[i] = exp(-TAU_R[i] * sky->glow_tint * w);
		qy += Y_ROW[i] * q[i];
	}
	for (int i = 0; i < 3; i++) {
		double c = f * rgb[i] * q[i] / qy + (1.0 - f) * sky->night[i];
		rgb[i] = c > 0.0 ? c : 0.0;
	}
}

CS_HD CS_COLD void cs_sky_sun_disk(const struct cs_sky *sky, cs_v3 dir, double rgb[3])
{
	rgb[0] = rgb[1] = rgb[2] = 0.0;
	if (!(v3_dot(dir, sky->sun_dir) >= sky->cos_sun_radius) || dir.z < 0.0)
		return;
	/* |dir x sun|^2 = sin^2 of the angle, without cancellation. */
	cs_v3 cr = v3_cross(dir, sky->sun_dir);
	double rho2 = v3_dot(cr, cr) / sky->sin2_sun_radius;
	double mu = sqrt(1.0 - (rho2 < 1.0 ? rho2 : 1.0));
	double ld = (1.0 - LIMB_U * (1.0 - mu)) / (1.0 - LIMB_U / 3.0);
	for (int i = 0; i < 3; i++)
		rgb[i] = sky->sun_radiance[i] * ld;
}
