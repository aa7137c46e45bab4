/* fuzz_provider - meteoblue and Open-Meteo JSON (weather/provider.h): the
 * checks mbfetch --check reports, parsing into hourly series, and what
 * wxinterp does with a series: values at and between the hours (nulls
 * bridged), the observations and the cloud layers the rules make, and a
 * merge of the file with itself. */
#include "weather/genus_rules.h"
#include "weather/provider.h"
#include "weather/series.h"

#include <stdint.h>
#include <stdlib.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void use_series(struct cs_series *s, const uint8_t *data, size_t size)
{
	char range[128];
	cs_series_range(s, range, sizeof range);
	double t0 = s->time_utc[0], t1 = s->time_utc[s->n - 1];
	const double ts[] = {t0, t0 + 1800.5, (t0 + t1) / 2, t1, t1 + 1, t0 - 60};
	for (size_t i = 0; i < sizeof ts / sizeof ts[0]; i++) {
		double v;
		for (int k = 0; k < CS_VAR_COUNT; k++)
			(void)cs_series_value(s, (enum cs_wxvar)k, ts[i], 10800.0, &v);
		struct cs_wx_obs ob;
		if (cs_series_obs(s, ts[i], 10800.0, &ob) == 0) {
			struct cs_wx_layer layers[CS_WX_MAX_LAYERS];
			int n = 0;
			enum cs_wx_rule rules[3];
			cs_wx_layers(&ob, s->alt_m, layers, &n, NULL);
			cs_wx_rules(&ob, rules);
			if (n < 0 || n > CS_WX_MAX_LAYERS)
				abort();
		}
	}
	struct cs_series b;
	if (cs_provider_parse((const char *)data, size, "again", &b) != 0)
		abort(); /* the same bytes parse the same way */
	double km;
	(void)cs_series_merge(s, &b, &km);
	cs_series_free(&b);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	struct cs_problems pr;
	enum cs_provider p;
	(void)cs_provider_detect((const char *)data, size, &p);
	(void)cs_provider_check((const char *)data, size, &pr);
	struct cs_series s;
	int parsed = cs_provider_parse((const char *)data, size, "fuzz.json", &s);
	if (parsed == 0 && s.n > 0)
		use_series(&s, data, size);
	cs_series_free(&s);
	return 0;
}
