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
};

/* Records a printf-style message for this thread and returns code. */
int cs_error(int code, const char *fmt, ...)
	__attribute__((format(printf, 2, 3)));

/* The last message recorded on this thread ("" if none). */
const char *cs_errmsg(void);

#endif
