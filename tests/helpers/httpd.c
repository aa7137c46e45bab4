/* httpd - a scripted HTTP/1.1 server for the tool tests.  Binds 127.0.0.1
 * on a port the system picks, prints the port on standard output, serves
 * one connection at a time and exits by itself after --lifetime seconds.
 * It never connects anywhere.
 *
 *   httpd DIR [--log FILE] [--lifetime SECONDS]
 *
 * A request for /CASE/anything?query gets the response in DIR/CASE/N,
 * where N counts the requests to CASE (1, 2, ...); when DIR/CASE/N is
 * missing, the highest existing lower number is served again.  A response
 * file is a status line without the protocol ("500 Internal Server
 * Error"), header lines, an empty line and the body.  In the whole file
 * @QUERY@ becomes the request's query string and @TARGET@ its target.
 * Headers the server acts on, and does not send:
 *   X-Test-Hang: 1       read the request, never answer (until exit)
 *   X-Test-Delay-Ms: N   wait N ms before answering
 *   X-Test-Repeat: N     send the body N times
 *   X-Test-No-Length: 1  no Content-Length: the body ends at the close
 * Content-Length is added unless the file sets one (a larger one makes a
 * cut transfer).  Each request is logged as "CASE N TARGET" to --log. */
#include <arpa/inet.h>
#include <errno.h>
#include <netinet/in.h>
#include <poll.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <time.h>
#include <unistd.h>

#define MAX_CASES 128
#define MAX_HUNG 64

static struct { char name[64]; int count; } cases[MAX_CASES];
static int ncases;
static int hung[MAX_HUNG], nhung;

static double now_s(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

static int next_count(const char *name)
{
	for (int i = 0; i < ncases; i++)
		if (strcmp(cases[i].name, name) == 0)
			return ++cases[i].count;
	if (ncases == MAX_CASES)
		return 1;
	snprintf(cases[ncases].name, sizeof cases[ncases].name, "%s", name);
	cases[ncases].count = 1;
	return cases[ncases++].count;
}

static char *read_file(const char *path, size_t *len)
{
	FILE *f = fopen(path, "rb");
	if (f == NULL)
		return NULL;
	size_t cap = 4096, n = 0;
	char *buf = malloc(cap);
	size_t r;
	while (buf && (r = fread(buf + n, 1, cap - n - 1, f)) > 0) {
		n += r;
		if (n + 1 == cap) {
			char *nb = realloc(buf, cap * 2);
			if (nb == NULL) {
				free(buf);
				buf = NULL;
				break;
			}
			buf = nb;
			cap *= 2;
		}
	}
	fclose(f);
	if (buf) {
		buf[n] = '\0';
		*len = n;
	}
	return buf;
}

/* s with every "@QUERY@" and "@TARGET@" replaced; a new string. */
static char *substitute(const char *s, const char *query, const char *target)
{
	size_t cap = strlen(s) + 1, ql = strlen(query), tl = strlen(target);
	for (const char *p = s; (p = strchr(p, '@')) != NULL; p++)
		cap += ql + tl;
	char *out = malloc(cap), *o = out;
	if (out == NULL)
		return NULL;
	while (*s) {
		if (strncmp(s, "@QUERY@", 7) == 0) {
			memcpy(o, query, ql);
			o += ql;
			s += 7;
		} else if (strncmp(s, "@TARGET@", 8) == 0) {
			memcpy(o, target, tl);
			o += tl;
			s += 8;
		} else {
			*o++ = *s++;
		}
	}
	*o = '\0';
	return out;
}

static int send_all(int fd, const char *p, size_t n)
{
	while (n > 0) {
		ssize_t w = send(fd, p, n, MSG_NOSIGNAL);
		if (w < 0 && errno == EINTR)
			continue;
		if (w <= 0)
			return -1;
		p += w;
		n -= (size_t)w;
	}
	return 0;
}

static void close_gently(int fd)
{
	shutdown(fd, SHUT_WR);
	char buf[512];
	struct timeval tv = {0, 200000};
	setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
	while (recv(fd, buf, sizeof buf, 0) > 0)
		;
	close(fd);
}

static void respond_text(int fd, const char *status, const char *body)
{
	char head[256];
	int n = snprintf(head, sizeof head, "HTTP/1.1 %s\r\nContent-Type: text/plain\r\n"
			 "Content-Length: %zu\r\nConnection: close\r\n\r\n",
			 status, strlen(body));
	if (send_all(fd, head, (size_t)n) == 0)
		send_all(fd, body, strlen(body));
	close_gently(fd);
}

/* Sends the scripted response in text; returns 1 if the connection is to
 * be held open unanswered. */
static int respond(int fd, char *text)
{
	char *body = strstr(text, "\n\n");
	if (body) {
		*body = '\0';
		body += 2;
	} else {
		body = text + strlen(text);
	}
	long repeat = 1, delay_ms = 0;
	int hang = 0, no_length = 0, has_length = 0;
	size_t cap = strlen(text) + 256, hl = 0;
	char *head = malloc(cap);
	if (head == NULL)
		return 0;
	char *save = NULL;
	int first = 1;
	for (char *line = strtok_r(text, "\n", &save); line;
	     line = strtok_r(NULL, "\n", &save)) {
		line[strcspn(line, "\r")] = '\0';
		if (first) {
			hl += (size_t)snprintf(head + hl, cap - hl, "HTTP/1.1 %s\r\n", line);
			first = 0;
		} else if (strncasecmp(line, "X-Test-Hang:", 12) == 0) {
			hang = 1;
		} else if (strncasecmp(line, "X-Test-Delay-Ms:", 16) == 0) {
			delay_ms = atol(line + 16);
		} else if (strncasecmp(line, "X-Test-Repeat:", 14) == 0) {
			repeat = atol(line + 14);
		} else if (strncasecmp(line, "X-Test-No-Length:", 17) == 0) {
			no_length = 1;
		} else {
			has_length |= strncasecmp(line, "Content-Length:", 15) == 0;
			hl += (size_t)snprintf(head + hl, cap - hl, "%s\r\n", line);
		}
	}
	if (hang) {
		free(head);
		return 1;
	}
	size_t blen = strlen(body);
	if (!has_length && !no_length)
		hl += (size_t)snprintf(head + hl, cap - hl, "Content-Length: %zu\r\n",
				       blen * (size_t)(repeat > 0 ? repeat : 0));
	hl += (size_t)snprintf(head + hl, cap - hl, "Connection: close\r\n\r\n");
	if (delay_ms > 0) {
		struct timespec ts = {delay_ms / 1000, (delay_ms % 1000) * 1000000L};
		nanosleep(&ts, NULL);
	}
	int ok = send_all(fd, head, hl) == 0;
	for (long r = 0; ok && r < repeat; r++)
		ok = send_all(fd, body, blen) == 0;
	free(head);
	close_gently(fd);
	return 0;
}

/* Reads the request head; returns its length or -1. */
static int read_head(int fd, char *buf, size_t size)
{
	struct timeval tv = {2, 0};
	setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
	size_t n = 0;
	while (n + 1 < size) {
		ssize_t r = recv(fd, buf + n, size - n - 1, 0);
		if (r < 0 && errno == EINTR)
			continue;
		if (r <= 0)
			return -1;
		n += (size_t)r;
		buf[n] = '\0';
		if (strstr(buf, "\r\n\r\n"))
			return (int)n;
	}
	return -1;
}

static void serve(int fd, const char *dir, FILE *log)
{
	char req[16384];
	if (read_head(fd, req, sizeof req) < 0) {
		close(fd);
		return;
	}
	char *sp1 = strchr(req, ' ');
	char *sp2 = sp1 ? strchr(sp1 + 1, ' ') : NULL;
	if (sp2 == NULL || sp1[1] != '/') {
		respond_text(fd, "400 Bad Request", "bad request line\n");
		return;
	}
	*sp2 = '\0';
	char *target = sp1 + 1;
	char path[8192], name[64];
	const char *q = strchr(target, '?');
	const char *query = q ? q + 1 : "";
	size_t nl = strcspn(target + 1, "/?");
	if (nl == 0 || nl >= sizeof name) {
		respond_text(fd, "404 Not Found", "no case in the path\n");
		return;
	}
	memcpy(name, target + 1, nl);
	name[nl] = '\0';
	for (char *c = name; *c; c++)
		if (!(*c == '-' || *c == '_' || (*c >= '0' && *c <= '9') ||
		      (*c >= 'a' && *c <= 'z') || (*c >= 'A' && *c <= 'Z'))) {
			respond_text(fd, "404 Not Found", "bad case name\n");
			return;
		}
	int count = next_count(name);
	if (log) {
		fprintf(log, "%s %d %s\n", name, count, target);
		fflush(log);
	}
	char *text = NULL;
	size_t len = 0;
	for (int k = count; k >= 1 && text == NULL; k--) {
		snprintf(path, sizeof path, "%s/%s/%d", dir, name, k);
		text = read_file(path, &len);
	}
	if (text == NULL) {
		respond_text(fd, "404 Not Found", "no such case\n");
		return;
	}
	char *full = substitute(text, query, target);
	free(text);
	if (full && respond(fd, full) && nhung < MAX_HUNG)
		hung[nhung++] = fd;
	else if (full == NULL)
		close(fd);
	free(full);
}

int main(int argc, char **argv)
{
	const char *dir = NULL, *log_path = NULL;
	double lifetime = 30.0;
	for (int i = 1; i < argc; i++) {
		if (strcmp(argv[i], "--log") == 0 && i + 1 < argc)
			log_path = argv[++i];
		else if (strcmp(argv[i], "--lifetime") == 0 && i + 1 < argc)
			lifetime = atof(argv[++i]);
		else if (dir == NULL && argv[i][0] != '-')
			dir = argv[i];
		else
			dir = NULL, i = argc;
	}
	if (dir == NULL || !(lifetime > 0.0 && lifetime <= 600.0)) {
		fprintf(stderr, "usage: httpd DIR [--log FILE] [--lifetime SECONDS (<= 600)]\n");
		return 2;
	}
	signal(SIGPIPE, SIG_IGN);
	FILE *log = log_path ? fopen(log_path, "a") : NULL;
	if (log_path && log == NULL) {
		perror(log_path);
		return 1;
	}
	int ls = socket(AF_INET, SOCK_STREAM, 0);
	struct sockaddr_in a;
	memset(&a, 0, sizeof a);
	a.sin_family = AF_INET;
	a.sin_port = 0;
	a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
	socklen_t al = sizeof a;
	if (ls < 0 || bind(ls, (struct sockaddr *)&a, sizeof a) < 0 ||
	    listen(ls, 16) < 0 || getsockname(ls, (struct sockaddr *)&a, &al) < 0) {
		perror("httpd: 127.0.0.1");
		return 1;
	}
	printf("%d\n", ntohs(a.sin_port));
	fflush(stdout);
	double end = now_s() + lifetime;
	for (double left; (left = end - now_s()) > 0;) {
		struct pollfd p = {.fd = ls, .events = POLLIN};
		int ms = left > 0.2 ? 200 : (int)(left * 1000.0) + 1;
		if (poll(&p, 1, ms) <= 0)
			continue;
		int fd = accept(ls, NULL, NULL);
		if (fd >= 0)
			serve(fd, dir, log);
	}
	for (int i = 0; i < nhung; i++)
		close(hung[i]);
	close(ls);
	if (log)
		fclose(log);
	return 0;
}
