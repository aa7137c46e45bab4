/* viewfile.h - named viewpoints from a user's file (cloudrender --views),
 * beside the built-in ones of places.h.
 *
 * The file: one view a line, fields separated by blanks,
 *     NAME LAT_DEG LON_DEG ALT_M AZIMUTH_DEG ELEVATION_DEG FOV_DEG [DESCRIPTION...]
 * the camera at LAT_DEG, LON_DEG (WGS84) and ALT_M metres above sea level,
 * looking along AZIMUTH_DEG (from north, clockwise) and ELEVATION_DEG with
 * a horizontal field of view of FOV_DEG; '#' starts a comment, blank lines
 * are skipped.  Names: 1..31 letters, digits, '-' or '_', unique (case
 * aside) in the file; a name also built in means the file's view. */
#ifndef CS_VIEWFILE_H
#define CS_VIEWFILE_H

#include "weather/places.h"

#define CS_VIEWFILE_MAX 64      /* views in one file */
#define CS_VIEWFILE_NAME 32     /* bytes of a name, with its NUL */
#define CS_VIEWFILE_TEXT 160    /* bytes of a description, with its NUL */

/* The views of one file; each view's place is its own (alt_m the camera's
 * height, eye_m 0). */
struct cs_viewset {
	int n;
	struct cs_view views[CS_VIEWFILE_MAX];
	struct cs_place places[CS_VIEWFILE_MAX];
	char names[CS_VIEWFILE_MAX][CS_VIEWFILE_NAME];
	char text[CS_VIEWFILE_MAX][CS_VIEWFILE_TEXT];
};

/* Reads a view file into *set: 0, CS_EIO (cannot open or read it) or
 * CS_EDATA (a bad line: the message names its number and what is wrong). */
int cs_viewset_read(const char *path, struct cs_viewset *set);

/* The view of that name (case-insensitive): the file's (set may be NULL),
 * else the built-in one, else NULL. */
const struct cs_view *cs_viewset_find(const struct cs_viewset *set, const char *name);

#endif
