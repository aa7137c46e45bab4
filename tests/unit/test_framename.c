/* Frame numbering of output names: the names ffmpeg's image2 muxer
 * (libavformat av_get_frame_filename2) gives the same patterns, and the
 * patterns it refuses. */
#include "test.h"

#include "core/err.h"
#include "core/framename.h"

static int named(const char *pattern, long long n, const char *want)
{
	char buf[256];
	int rc = cs_framename_format(pattern, n, buf, sizeof buf);
	if (rc != CS_OK || strcmp(buf, want) != 0) {
		printf("  '%s' %lld -> %s, expected %s\n", pattern, n,
		       rc == CS_OK ? buf : cs_errmsg(), want);
		return 0;
	}
	return 1;
}

static void framename_numbers_as_ffmpeg_image2_does(void)
{
	/* what `ffmpeg -i in.mp4 -start_number N PATTERN` names frame N */
	CHECK(named("frames/%05d.png", 42, "frames/00042.png"));
	CHECK(named("img%03d.exr", 7, "img007.exr"));
	CHECK(named("img%d.png", 0, "img0.png"));
	CHECK(named("img%d.png", 1234567, "img1234567.png"));
	CHECK(named("%5d.png", 42, "00042.png"));  /* ffmpeg pads %5d with zeros */
	CHECK(named("%02d.png", 123, "123.png"));  /* wider numbers are not cut */
	CHECK(named("%1d", 9, "9"));
	CHECK(named("100%%-%04d.png", 3, "100%-0003.png"));
	CHECK(named("a%%b%%c%d", 5, "a%b%c5"));
	CHECK(named("%d%%", 12, "12%"));
}

static void framename_literal_names_stay_literal(void)
{
	CHECK(cs_framename_check("sky.png") == 0);
	CHECK(cs_framename_check("50%%.png") == 0);
	CHECK(cs_framename_check("-") == 0);
	CHECK(named("sky.png", 3, "sky.png"));
	CHECK(named("50%%.png", 3, "50%.png"));
	CHECK(cs_framename_check("f%03d.png") == 1);
	CHECK(cs_framename_check("%d") == 1);
}

static int refused(const char *pattern, const char *why)
{
	char buf[64];
	int ok = cs_framename_check(pattern) == CS_EINVAL &&
		 cs_framename_format(pattern, 1, buf, sizeof buf) == CS_EINVAL &&
		 strstr(cs_errmsg(), why) != NULL;
	if (!ok)
		printf("  '%s' not refused with '%s' (%s)\n", pattern, why, cs_errmsg());
	return ok;
}

static void framename_refuses_other_conversions(void)
{
	CHECK(refused("f%s.png", "'%s' at byte 1 is not a frame number"));
	CHECK(refused("f%x.png", "'%x'"));
	CHECK(refused("f%i.png", "'%i'"));
	CHECK(refused("f%-5d.png", "'%-'"));
	CHECK(refused("f%ld.png", "'%l'"));
	CHECK(refused("f%5.png", "'%5.'"));
	CHECK(refused("50%.png", "'%.' at byte 2"));
	CHECK(refused("end%", "'%' at byte 3"));
	CHECK(refused("end%05", "'%05' at byte 3"));
	CHECK(refused("%d-%d.png", "more than one frame number (at byte 3)"));
	CHECK(refused("%021d.png", "more than 20 digits"));
	CHECK(named("%020d", 1, "00000000000000000001"));
}

static void framename_refuses_what_does_not_fit(void)
{
	char buf[8];
	/* "0001.png" and its NUL are 9 bytes; "001.png" and its NUL 8 */
	CHECK(cs_framename_format("%04d.png", 1, buf, sizeof buf) == CS_EINVAL);
	CHECK(cs_framename_format("%03d.png", 1, buf, sizeof buf) == CS_OK);
	CHECK(strcmp(buf, "001.png") == 0);
	CHECK(cs_framename_format("%d", -1, buf, sizeof buf) == CS_EINVAL);
}

/* The cases, in the order they run: their number is the plan. */
static const struct t_case t_cases[] = {
	CASE(framename_numbers_as_ffmpeg_image2_does),
	CASE(framename_literal_names_stay_literal),
	CASE(framename_refuses_other_conversions),
	CASE(framename_refuses_what_does_not_fit),
};

int main(void)
{
	T_RUN_TABLE(t_cases);
	TEST_EXIT();
}
