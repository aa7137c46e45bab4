/* err.h - error values and messages for the cloudscape library.
 *
 * Library functions return 0 on success or a negative CS_E* code, and record
 * a one-line message (no program name, no newline) that the calling tool
 * prints.  The message is per thread.  The library never prints or exits. */
#ifndef CS_ERR_H
#define CS_ERR_H

enum cs_status {
	CS_OK = 0,
	CS_EINVAL = -1, /* bad argument: the caller's (usually the user's) mistake */
	CS_EIO = -2,    /* the operating system refused: open, write, rename... */
	CS_EDATA = -3,  /* a file or stream has bad or inconsistent contents */
	CS_ENOMEM = -4, /* allocation failed */
	CS_ECANCELED = -5, /* the caller's progress callback asked to stop */
	/* fetching (net/): what a provider or the network answered */
	CS_EAUTH = -20,    /* the provider refused the credentials, or none */
	CS_EREQUEST = -21, /* the provider refused the request (HTTP 400, 404...) */
	CS_ERATE = -22,    /* a rate limit (HTTP 429) */
	CS_ENET = -23,     /* no answer: connect, DNS, timeout, cut transfer, 5xx */
};

/* Records a printf-style message for this thread and returns code. */
int cs_error(int code, const char *fmt, ...)
	__attribute__((format(printf, 2, 3)));

/* Returns from the calling function with the code of a call that failed. */
#define CS_TRY(call)                                                          \
	do {                                                                  \
		int cs_try_rc_ = (call);                                      \
		if (cs_try_rc_ != CS_OK)                                      \
			return cs_try_rc_;                                    \
	} while (0)

/* The last message recorded on this thread ("" if none). */
const char *cs_errmsg(void);

#endif
