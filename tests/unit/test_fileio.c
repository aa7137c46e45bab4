/* Whole writes: every byte arrives through a pipe smaller than the data
 * (short writes), and an atomic file holds exactly what was written. */
#include "test.h"

#include "core/err.h"
#include "core/fileio.h"

#include <pthread.h>
#include <stdlib.h>
#include <unistd.h>

#define BIG (1 << 20) /* far above a pipe's 64 KiB buffer */

struct drain {
	int fd;
	unsigned char *got;
	size_t n;
};

static void *drain_pipe(void *arg)
{
	struct drain *d = arg;
	ssize_t r;
	while (d->n < BIG && (r = read(d->fd, d->got + d->n, BIG - d->n)) > 0)
		d->n += (size_t)r;
	return NULL;
}

static void write_all_delivers_every_byte_through_a_pipe(void)
{
	unsigned char *data = malloc(BIG), *got = malloc(BIG);
	int p[2];
	CHECK(data && got && pipe(p) == 0);
	if (!data || !got)
		return;
	for (size_t i = 0; i < BIG; i++)
		data[i] = (unsigned char)(i * 2654435761u >> 24);
	struct drain d = {p[0], got, 0};
	pthread_t th;
	CHECK(pthread_create(&th, NULL, drain_pipe, &d) == 0);
	CHECK(cs_write_all(p[1], data, BIG) == 0);
	close(p[1]);
	pthread_join(th, NULL);
	close(p[0]);
	CHECK(d.n == BIG && memcmp(data, got, BIG) == 0);
	free(data);
	free(got);
}

static void write_all_fails_on_a_closed_descriptor(void)
{
	int p[2];
	CHECK(pipe(p) == 0);
	close(p[1]);
	CHECK(cs_write_all(p[1], "x", 1) == -1);
	close(p[0]);
}

static void write_file_replaces_the_file_whole(void)
{
	char path[] = "/tmp/cs-test-fileio-XXXXXX";
	int fd = mkstemp(path);
	CHECK(fd >= 0);
	close(fd);
	CHECK(cs_write_file(path, "old text", 8) == CS_OK);
	CHECK(cs_write_file(path, "new", 3) == CS_OK);
	unsigned char *back = NULL;
	size_t n = 0;
	CHECK(cs_read_all(path, 100, &back, &n) == CS_OK);
	CHECK(n == 3 && back && memcmp(back, "new", 3) == 0);
	free(back);
	CHECK(cs_write_file("/nonexistent-dir/x", "a", 1) == CS_EIO);
	unlink(path);
}

/* The cases, in the order they run: their number is the plan. */
static const struct t_case t_cases[] = {
	CASE(write_all_delivers_every_byte_through_a_pipe),
	CASE(write_all_fails_on_a_closed_descriptor),
	CASE(write_file_replaces_the_file_whole),
};

int main(void)
{
	T_RUN_TABLE(t_cases);
	TEST_EXIT();
}
