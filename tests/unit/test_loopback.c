/* test_loopback.c - which hosts mbfetch counts as this machine (no warning
 * about an API key sent unencrypted): exactly localhost, 127.0.0.0/8 and
 * ::1 (RFC 6761 6.3 for localhost, RFC 1122 3.2.1.3 for 127/8, RFC 4291
 * 2.5.3 for ::1). */
#include "apps/mbfetch_run.h"
#include "test.h"

static void loopback_hosts_are_exactly_localhost_127_8_and_ipv6_1(void)
{
	static const char *const local[] = {
		"http://localhost/x", "http://localhost:8080/x", "http://LocalHost/",
		"http://localhost./x", "http://localhost", "http://127.0.0.1:9/x",
		"http://127.1.2.3/", "http://127.255.255.254?q", "http://[::1]:8080/x",
		"http://[0:0:0:0:0:0:0:1]/", "http://user:pw@localhost/x",
	};
	static const char *const remote[] = {
		"http://localhost.example.invalid/x", "http://localhostx/",
		"http://localhost.evil.example:80/", "http://127.0.0.1.example.com/",
		"http://127.example.com/", "http://128.0.0.1/", "http://1127.0.0.1/",
		"http://[::2]/", "http://[::1x]/", "http://evil.example/localhost",
		"http://localhost@evil.example/", "http://my-localhost/", "http:///",
	};
	for (size_t i = 0; i < sizeof local / sizeof local[0]; i++)
		if (!cs_mbfetch_is_loopback(local[i])) {
			printf("  %s: not taken as local\n", local[i]);
			t_case_failed = 1;
		}
	for (size_t i = 0; i < sizeof remote / sizeof remote[0]; i++)
		if (cs_mbfetch_is_loopback(remote[i])) {
			printf("  %s: taken as local\n", remote[i]);
			t_case_failed = 1;
		}
}

static const struct t_case t_cases[] = {
	CASE(loopback_hosts_are_exactly_localhost_127_8_and_ipv6_1),
};

int main(void)
{
	T_RUN_TABLE(t_cases);
	TEST_EXIT();
}
