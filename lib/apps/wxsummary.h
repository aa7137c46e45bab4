/* wxsummary.h - wxinterp --summary: what the sky does hour by hour (or day
 * by day), as a table a person reads or as JSON Lines (man 1 wxinterp,
 * SUMMARY). */
#ifndef CS_WXSUMMARY_H
#define CS_WXSUMMARY_H

#include "core/fileio.h"
#include "weather/genus_rules.h"
#include "weather/wx.h"

/* One time of the summary: the state and the observation it came from. */
struct cs_wxsum_row {
	struct cs_wx wx;
	struct cs_wx_obs ob;
};

/* The cloud cover of a row, 0..1: the provider's total cover when the file
 * has it, else the cover of independent étages, 1 - (1-low)(1-mid)(1-high). */
double cs_wxsum_cover(const struct cs_wxsum_row *r);

/* "Ci", "Cc", "Cs", "Ac", "As", "Ns", "Sc", "St", "Cu", "Cb" (WMO). */
const char *cs_genus_abbrev(enum cs_genus g);

/* Writes the summary of n rows (times increasing, step_s apart) to of:
 * one line per row, or with daily one per UTC day; json: JSON Lines. */
int cs_wxsum_write(const struct cs_wxsum_row *rows, long n, double step_s,
		   int daily, int json, struct cs_outfile *of);

#endif
