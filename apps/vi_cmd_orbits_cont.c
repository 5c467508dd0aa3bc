/* vi_cmd_orbits_cont.c - `orbits --continue`: print a branch followed by the
 * library's continuation (vi_cont.h), as text or JSON; the numerics are
 * the library's, the parameter changes on the model (vi_param.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vibroimpact.h"
#include "vibroimpact/vi_scene.h"
#include "vibroimpact/vi_scene_param.h"
#include "vi_diagram.h"

static const char *const ev_json[] = {"period_doubling", "fold_or_pitchfork",
                                      "neimark_sacker", "grazing",
                                      "grazing_impact", "fold", "lost", "closed"};

typedef struct out {
  int json, arc, nev, npts;
  const char *key;
  char events[8192];
} out;

static void point(out *o, const vi_cont *c)
{
  double p, vn, t, rho;
  int ok;
  vi_cont_point(c, &p, &vn, &t, &rho, &ok);
  if (o->json)
    printf("%s{\"param\": %.17g, \"vN\": %.17g, \"impact_time\": %.17g, "
           "\"max_multiplier\": %.17g, \"stable\": %s, \"admissible\": %s}",
           o->npts ? ", " : "", p, vn, t, rho, rho < 1 ? "true" : "false",
           ok ? "true" : "false");
  else
    printf("  %14.10g %14.10g %12.8g %8s %s\n", p, vn, rho, rho < 1 ? "yes" : "no",
           ok ? "yes" : "no");
  o->npts++;
}

/* An event as the text line and the JSON entry of its method. */
static void event(out *o, int type, double p, double vn, double re, double im,
                  int adm)
{
  size_t k = strlen(o->events), len = sizeof o->events - k;
  char *e = o->events + k;
  const char *sep = o->nev++ ? ", " : "", *name = ev_json[type];
  int graze = type == VI_CONT_GRAZING || type == VI_CONT_GRAZING_IMPACT;
  const char *tname = type == VI_CONT_GRAZING_IMPACT ? "grazing impact" : name;
  if (type == VI_CONT_LOST) {
    snprintf(e, len, "%s{\"type\": \"lost\", \"param\": %.17g, \"vN\": %.17g, "
             "\"multiplier\": [%.17g, %.17g]}", sep, p, vn, re, im);
    if (!o->json)
      printf("  the branch ends at %s = %.12g (v_N %.10g, largest multiplier "
             "%.6g%+.6gi): a fold, or the orbit stops impacting\n", o->key, p, vn, re, im);
  } else if (type == VI_CONT_CLOSED) {
    snprintf(e, len, "%s{\"type\": \"closed\", \"param\": %.17g}", sep, p);
    if (!o->json) printf("  the branch closes on itself at %s = %.10g\n", o->key, p);
  } else if (type == VI_CONT_FOLD) {
    snprintf(e, len, "%s{\"type\": \"fold\", \"param\": %.17g, \"admissible\": %s}",
             sep, p, adm ? "true" : "false");
    if (!o->json) printf("    -> fold at %s = %.12g (the branch turns back)%s\n",
                         o->key, p, adm ? "" : " (not admissible)");
  } else if (o->arc) { /* located by interpolation */
    if (graze) snprintf(e, len, "%s{\"type\": \"%s\", \"param\": %.17g}", sep, name, p);
    else snprintf(e, len, "%s{\"type\": \"%s\", \"param\": %.17g, \"admissible\": %s}",
                  sep, name, p, adm ? "true" : "false");
    if (!o->json && graze) printf("    -> %s at %s = %.12g\n", tname, o->key, p);
    else if (!o->json) printf("    -> %s at %s = %.12g (multiplier %.10g%+.3gi)%s\n", name,
                              o->key, p, re, im, adm ? "" : " (not admissible)");
  } else { /* bisected */
    if (graze) snprintf(e, len, "%s{\"type\": \"%s\", \"param\": %.17g, \"vN\": %.17g}",
                        sep, name, p, vn);
    else snprintf(e, len, "%s{\"type\": \"%s\", \"param\": %.17g, \"multiplier\": "
                  "[%.17g, %.17g]}", sep, name, p, re, im);
    if (!o->json)
      printf("    -> %s at %s = %.12g%s\n", tname, o->key, p,
             !graze ? " (a multiplier on the unit circle)"
             : type == VI_CONT_GRAZING ? " (the gap between impacts touches the stop)"
                                       : " (v_N = 0)");
  }
}

static void events(out *o, const vi_cont *c)
{
  for (int i = 0; i < vi_cont_num_events(c); i++) {
    int type, adm;
    double p, vn, re, im;
    vi_cont_event(c, i, &type, &p, &vn, &re, &im, &adm);
    event(o, type, p, vn, re, im, adm);
  }
}

static void header(const out *o, int np, double p0, double to)
{
  if (o->json)
    printf("{\"key\": \"%s\", \"n\": %d, \"m\": 1, %s\"branch\": [", o->key, np,
           o->arc ? "\"method\": \"pseudo-arclength\", " : "");
  else
    printf("P(%d,1) orbit followed in %s from %.10g %s %.10g%s\n  %14s %14s %12s %8s %s\n",
           np, o->key, p0, o->arc ? "towards" : "to", to,
           o->arc ? " by pseudo-arclength" : "", o->key, "v_N", "max|mu|", "stable",
           "admissible");
}

int vi_orbits_follow(const vi_model *m, const vi_scene *sc, const char *key,
                     int arclength, double to, int steps, int np, double t0,
                     const double *x0, const double *v0, int json, char *err,
                     int errlen)
{
  char pkey[64];
  vi_diag d;
  vi_cont *c = NULL;
  out *o = calloc(1, sizeof *o);
  if (!o) return 1;
  o->json = json;
  o->arc = arclength;
  o->key = key;
  int st = vi_scene_param_key(sc, key, pkey, sizeof pkey, &d), rc = 2;
  double p0;
  if (st) vi_diag_format(&d, err, errlen);
  else if ((st = vi_model_param(m, pkey, &p0))) /* an index beyond the model's */
    snprintf(err, (size_t)errlen, "%s", vi_model_errmsg(m));
  else if ((st = vi_cont_create(m, pkey, np, arclength ? VI_CONT_ARCLENGTH : VI_CONT_NATURAL, &c)) ||
           (st = vi_cont_set_range(c, to, steps)) || (st = vi_cont_set_orbit(c, t0, x0, v0)))
    snprintf(err, (size_t)errlen, "%s: %s", key, vi_strerror(st));
  if (st) goto done;
  if (arclength) header(o, np, p0, to);
  st = vi_cont_iterate(c);
  if (st) {
    snprintf(err, (size_t)errlen, "%s", vi_cont_errmsg(c));
    rc = arclength ? 0 : 2; /* the header is out: the empty branch stands */
    if (arclength && json) printf("], \"events\": []}\n");
    if (arclength) rc = 1;
    goto done;
  }
  if (!arclength) header(o, np, p0, to);
  rc = 0;
  for (;;) {
    if (!st) point(o, c);
    events(o, c);
    if (vi_cont_done(c)) break;
    st = vi_cont_iterate(c);
  }
  if (vi_cont_done(c) == VI_CONT_CORRECTOR && !json) {
    double p;
    vi_cont_point(c, &p, NULL, NULL, NULL, NULL);
    printf("  the corrector fails after %s = %.12g\n", key, p);
  }
  if (json) printf("], \"events\": [%s]}\n", o->events);
done:
  vi_cont_destroy(&c);
  free(o);
  return rc;
}
