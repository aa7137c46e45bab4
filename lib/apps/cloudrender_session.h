/* cloudrender_session.h - inside cloudrender: what the frames of a run
 * share (cloudrender_run.c), for the run over a series of frames
 * (cloudrender_series.c). */
#ifndef CS_CLOUDRENDER_SESSION_H
#define CS_CLOUDRENDER_SESSION_H

#include "apps/cloudrender_run.h"

struct cs_cr_session;

/* Checks the options that need no file (CS_EINVAL) and makes a session;
 * fills r->settings.  Close it whatever a later call returns. */
int cs_cr_session_open(const struct cs_cloudrender_opts *o, struct cs_cloudrender_result *r,
		       struct cs_cr_session **s);
/* Reads or bakes the noise and makes the frame buffer (r->t_noise_s). */
int cs_cr_session_load(struct cs_cr_session *s, const struct cs_cloudrender_opts *o,
		       struct cs_cloudrender_result *r);
/* The scene and camera of r->wx, without rendering: the look the default
 * view chooses (r->look_az_deg, r->look_el_deg, r->look_why). */
int cs_cr_session_look(struct cs_cr_session *s, const struct cs_cloudrender_opts *o,
		       struct cs_cloudrender_result *r);
/* Renders r->wx with o into the session's frame buffer, *px (5 floats a
 * pixel, as cs_cr_write takes them), and measures it; writes nothing. */
int cs_cr_session_render(struct cs_cr_session *s, const struct cs_cloudrender_opts *o,
			 struct cs_cloudrender_result *r, float **px);
/* Writes the outputs of o (every one or none) of the frame px that r
 * describes (r->t_write_s, r->exposure_ev); px gets the caption. */
int cs_cr_write(const struct cs_cloudrender_opts *o, struct cs_cloudrender_result *r, float *px);
/* Renders r->wx with o (its outputs the frame's names) and writes them. */
int cs_cr_session_frame(struct cs_cr_session *s, const struct cs_cloudrender_opts *o,
			struct cs_cloudrender_result *r);
/* Frees the session; r->scene (the last frame's) stays for the report. */
void cs_cr_session_close(struct cs_cr_session *s, struct cs_cloudrender_result *r);

#endif
