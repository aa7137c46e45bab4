/* Sets of outputs (core/fileio.h): all of them appear or none; checked
 * before the work; --no-clobber never replaces a file. */
#include "test.h"

#include "core/err.h"
#include "core/fileio.h"

#include <dirent.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <unistd.h>

static char dir[256];

static const char *at(const char *name)
{
	static char buf[4][512];
	static int k;
	k = (k + 1) % 4;
	snprintf(buf[k], sizeof buf[k], "%s/%s", dir, name);
	return buf[k];
}

/* Entries in the test folder (temporaries included). */
static int entries(void)
{
	DIR *d = opendir(dir);
	int n = 0;
	for (struct dirent *e; d && (e = readdir(d)) != NULL;)
		n += e->d_name[0] != '.' || (e->d_name[1] != '\0' && e->d_name[1] != '.');
	if (d)
		closedir(d);
	return n;
}

static void clean(void)
{
	DIR *d = opendir(dir);
	for (struct dirent *e; d && (e = readdir(d)) != NULL;)
		if (strcmp(e->d_name, ".") && strcmp(e->d_name, "..")) {
			unlink(at(e->d_name));
			rmdir(at(e->d_name));
		}
	if (d)
		closedir(d);
}

/* Writes a and b as one set; with intrude, a folder appears at b while
 * the work runs (after the check, before the renames). */
static int write_two(int flags, int intrude, const char *a, const char *b)
{
	struct cs_outset s;
	struct cs_outfile *of;
	cs_outset_init(&s, flags);
	int rc = cs_outset_open(&s, a, &of);
	if (rc == CS_OK)
		rc = cs_outfile_write(of, "first\n", 6);
	if (rc == CS_OK)
		rc = cs_outset_open(&s, b, &of);
	if (rc == CS_OK)
		rc = cs_outfile_write(of, "second\n", 7);
	if (rc == CS_OK && intrude)
		mkdir(b, 0700);
	if (rc == CS_OK)
		rc = cs_outset_commit(&s);
	cs_outset_abort(&s);
	return rc;
}

static void a_set_appears_whole(void)
{
	clean();
	CHECK(write_two(0, 0, at("a.txt"), at("b.txt")) == CS_OK);
	CHECK(entries() == 2);
	CHECK(access(at("a.txt"), F_OK) == 0 && access(at("b.txt"), F_OK) == 0);
}

static void no_clobber_takes_back_what_it_placed_when_a_later_output_fails(void)
{
	clean();
	/* b turns into a folder between the check and the renames: a was
	 * already placed, and is removed again since it is new */
	CHECK(write_two(CS_OUT_NO_CLOBBER, 1, at("a.txt"), at("b.txt")) != CS_OK);
	CHECK(access(at("a.txt"), F_OK) != 0);
	CHECK(entries() == 1); /* only the folder b.txt: no temporaries */
}

static void no_clobber_refuses_an_existing_file_at_open_and_at_check(void)
{
	clean();
	FILE *f = fopen(at("old.txt"), "w");
	CHECK(f != NULL);
	if (f) {
		fputs("old\n", f);
		fclose(f);
	}
	const char *paths[2] = {at("new.txt"), at("old.txt")};
	CHECK(cs_outset_check(paths, 2, CS_OUT_NO_CLOBBER) == CS_EIO);
	CHECK_STR_CONTAINS(cs_errmsg(), "old.txt exists: not overwritten (--no-clobber)");
	CHECK(cs_outset_check(paths, 2, 0) == CS_OK);
	CHECK(write_two(CS_OUT_NO_CLOBBER, 0, at("new.txt"), at("old.txt")) == CS_EIO);
	CHECK(access(at("new.txt"), F_OK) != 0);
	CHECK(entries() == 1);
}

static void check_finds_twice_named_outputs_and_missing_folders(void)
{
	clean();
	const char *same[2] = {at("x.png"), at("./x.png")};
	CHECK(cs_outset_check(same, 2, 0) == CS_EINVAL);
	CHECK_STR_CONTAINS(cs_errmsg(), "named twice");
	const char *dash[2] = {"-", "-"};
	CHECK(cs_outset_check(dash, 2, 0) == CS_EINVAL);
	const char *nodir[2] = {at("a.png"), at("none/b.png")};
	CHECK(cs_outset_check(nodir, 2, 0) == CS_EIO);
	CHECK_STR_CONTAINS(cs_errmsg(), "none/b.png");
	mkdir(at("d.exr"), 0700);
	const char *isdir[1] = {at("d.exr")};
	CHECK(cs_outset_check(isdir, 1, 0) == CS_EIO);
	CHECK_STR_CONTAINS(cs_errmsg(), "Is a directory");
	CHECK(entries() == 1);
}

static const struct t_case t_cases[] = {
	CASE(a_set_appears_whole),
	CASE(no_clobber_takes_back_what_it_placed_when_a_later_output_fails),
	CASE(no_clobber_refuses_an_existing_file_at_open_and_at_check),
	CASE(check_finds_twice_named_outputs_and_missing_folders),
};

int main(void)
{
	snprintf(dir, sizeof dir, "%s/cs-outset.XXXXXX", getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp");
	if (mkdtemp(dir) == NULL)
		return 1;
	T_RUN_TABLE(t_cases);
	clean();
	rmdir(dir);
	TEST_EXIT();
}
