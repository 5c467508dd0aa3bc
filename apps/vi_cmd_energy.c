/* vi_cmd_energy.c - `vibroimpact energy`: the P(1,1) energy balance of a
 * scene (WB 11-13), per-mode ledger, and reduced-model restitution. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vi_app.h"
#include "vi_diagram.h"

/* Orbit of the reduced model with the first k modes and restitution r_S,
 * compared with the full orbit: impact velocity, deepest excursion from the
 * stop, impact phase.  Returns 0 if it is P(1,1) too. */
static int reduced_check(const vi_model *m, int k, double rS, double *vN,
                         double *gmin, double *phase, int *pn, int *pm)
{
  int *modes = malloc(sizeof(int) * k), ok = 1;
  vi_model *red = NULL;
  vi_orbit *o = NULL;
  if (!modes) return 1;
  for (int j = 0; j < k; j++)
    modes[j] = j;
  if (vi_model_create_reduced(m, modes, k, rS, &red) ||
      vi_orbit_create(red, &o) ||
      vi_orbit_set_direct_search(o, 0) || /* what the simulation settles on */
      vi_orbit_find(o))
    ok = 0;
  if (ok) {
    vi_orbit_classify(o, pn, pm);
    ok = *pn == 1 && *pm == 1 &&
         !vi_orbit_balance(o, NULL, phase, vN, NULL, NULL, NULL, NULL, NULL) &&
         !vi_orbit_min_gap(o, gmin);
  }
  vi_orbit_destroy(&o);
  vi_model_destroy(&red);
  free(modes);
  return !ok;
}


/* A JSON string: the scene's name is the user's text. */
static void json_str(const char *s)
{
  putchar('"');
  for (; *s; s++) {
    unsigned char ch = (unsigned char)*s;
    if (ch == '"' || ch == '\\')
      printf("\\%c", ch);
    else if (ch < 0x20)
      printf("\\u%04x", ch);
    else
      putchar(ch);
  }
  putchar('"');
}

/* The orbit's Floquet multipliers: a JSON member or a line of text. */
static void print_multipliers(const vi_orbit *orb, int n, int json)
{
  double *re = malloc(sizeof(double) * 4 * (size_t)n), *im = re ? re + (size_t)2 * n : NULL;
  if (!re || vi_orbit_multipliers(orb, re, im)) {
    free(re);
    return;
  }
  double rho = 0;
  for (int j = 0; j < 2 * n; j++) rho = fmax(rho, hypot(re[j], im[j]));
  printf(json ? ", \"multipliers\": [" : "  Floquet multipliers:");
  for (int j = 0; j < 2 * n; j++) {
    if (json) printf("%s[%.17g, %.17g]", j ? ", " : "", re[j], im[j]);
    else printf(" %.6g%+.6gi", re[j], im[j]);
  }
  if (json) printf("], \"stable\": %s", rho < 1 ? "true" : "false");
  else printf("  (largest modulus %.6g: %s)\n", rho, rho < 1 ? "stable" : "unstable");
  free(re);
}

/* WB 11-13 per stop of an analysed orbit (vi_orbit_stop_balance), with
 * its impacts: a JSON member or lines of text. */
static void print_stops(const vi_orbit *orb, const vi_model *m, int json)
{
  int ns = vi_model_num_stops(m), cnt = 0, sp[8];
  double t[8], vn[8], T = vi_model_forcing_period(m);
  if (vi_orbit_impacts(orb, &cnt, t, sp, vn, NULL, NULL, 1)) return;
  if (json) {
    printf(", \"impacts\": [");
    for (int j = 0; j < cnt; j++)
      printf("%s{\"stop\": %d, \"impact_phase\": %.17g, \"vN\": %.17g}",
             j ? ", " : "", sp[j], fmod(t[j], T), vn[j]);
    printf("], \"stops\": [");
  } else {
    for (int j = 0; j < cnt; j++)
      printf("  impact %d: stop %d, time mod T %.10g, v_N %.10g\n", j + 1,
             sp[j] + 1, fmod(t[j], T), vn[j]);
    printf("  %4s %7s %14s %14s %14s %14s %10s\n", "stop", "impacts", "KE_i",
           "RE", "IE", "r recovered", "|RE-IE|/KE");
  }
  for (int k = 0; k < ns; k++) {
    int c = 0;
    double KE, RE, IE, rr, cl;
    vi_orbit_stop_balance(orb, k, &c, &KE, &RE, &IE, &rr, &cl);
    if (json)
      printf("%s{\"stop\": %d, \"impacts\": %d, \"KE_i\": %.17g, \"RE\": "
             "%.17g, \"IE\": %.17g, \"r_recovered\": %.17g, \"closure\": %.6g}",
             k ? ", " : "", k, c, c ? KE : 0.0, c ? RE : 0.0, c ? IE : 0.0,
             c ? rr : 0.0, c ? cl : 0.0);
    else if (c)
      printf("  %4d %7d %14.8g %14.8g %14.8g %14.10f %10.3g\n", k + 1, c, KE,
             RE, IE, rr, cl);
    else
      printf("  %4d %7d\n", k + 1, 0);
  }
  if (json) printf("]");
}

/* The analysis to OUT.h5 (/model, /modal, /orbits); no file on failure. */
static int write_orbit(const app_opts *o, const vi_scene *sc, const vi_model *m,
                       const vi_orbit *orb)
{
  vi_writer *w = NULL;
  vi_diag d;
  char part[VI_APP_PATH + 8];
  if (vi_output_part(o->out_target, part, (int)sizeof part)) return 1;
  vi_app_arm_parts(part, NULL); /* a signal now removes it and exits */
  const app_writer_api *wa = vi_app_writer();
  if (!wa) return 1;
  if (wa->create(o->out_target, m, 0, &w, &d)) {
    fprintf(stderr, "vibroimpact: %s\n", d.message);
    return 1;
  }
  if (wa->write_header(w, sc, vi_scene_rtol(sc), vi_scene_atol(sc),
                       vi_scene_method(sc)) ||
      wa->orbit(w, orb) || wa->finish(w, 1)) {
    fprintf(stderr, "vibroimpact: %s\n", wa->errmsg(w));
    wa->abort(&w);
    return 1;
  }
  wa->abort(&w); /* frees; the file is already in place */
  return 0;
}

/* The scene can be analysed: harmonic forcing, no nonlinear springs.  0,
 * or 2 with the message printed. */
static int energy_scene_ok(const vi_scene *sc, const vi_model *m)
{
  if (!(vi_model_omega_forcing(m) > 0)) {
    fprintf(stderr, "vibroimpact: energy: the scene has no harmonic forcing, "
                    "so no P(1,1) orbit\n");
    return 2;
  }
  if (vi_app_text_nonlinear(vi_scene_text(sc))) {
    /* the orbit analysis integrates M, C, K and the stops only: a balance
     * without the springs' work would be the balance of another system */
    fprintf(stderr, "vibroimpact: energy: scene %s has nonlinear springs "
                    "(springs:); the WB 11-13 analysis is of the linear model "
                    "and would ignore them\n", vi_scene_name(sc));
    return 2;
  }
  return 0;
}

/* The orbit analysis with the command line's method and tolerances; 0, or
 * 1 with the message printed.  No file exists while the orbit is sought:
 * SIGINT/SIGTERM end the process at once (vi_app_arm_parts). */
static int energy_find(const app_opts *o, const vi_model *m, vi_orbit **orb)
{
  int st;
  if ((st = vi_orbit_create(m, orb)) ||
      (o->method >= 0 && (st = vi_orbit_set_method(*orb, o->method))) ||
      (o->rtol > 0 &&
       (st = vi_orbit_set_tolerances(
            *orb, o->rtol, o->atol > 0 ? o->atol : o->rtol * 1e-2))) ||
      (st = vi_orbit_set_initial(*orb, NULL, NULL)) ||
      (st = vi_orbit_find(*orb))) {
    /* without a handle the code is all there is: say what it needs */
    const char *why = *orb ? vi_orbit_errmsg(*orb)
                    : st == VI_ERR_FREQUENCY
                        ? "the analysis needs harmonic forcing (forcing.omega)"
                        : "the orbit analysis could not start";
    fprintf(stderr, "vibroimpact: energy: %s: %s\n", vi_strerror(st), why);
    return 1;
  }
  return 0;
}

/* A motion that is not P(1,1): a P(1, m) orbit over several stops is
 * reported per stop (exit 3); anything else is said on stderr (exit 1). */
static int energy_not_p11(const app_opts *o, const vi_scene *sc,
                          const vi_model *m, const vi_orbit *orb, int pn, int pm)
{
  int n = vi_model_n(m);
  int ana = vi_orbit_stop_balance(orb, 0, NULL, NULL, NULL, NULL, NULL, NULL) == VI_OK;
  if (o->json) {
    printf("{\"scene\": ");
    json_str(vi_scene_name(sc));
    printf(", ");
    vi_app_fe_json(stdout, sc);
    printf("\"P11\": false, \"periodic\": %s, ", pn ? "true" : "false");
    if (pn) printf("\"n\": %d, \"m\": %d", pn, pm);
    else printf("\"n\": null, \"m\": null, \"impacts_per_period\": %d", pm);
    if (ana) { /* a P(1, m) orbit over several stops: WB 11-13 per stop */
      print_stops(orb, m, 1);
      print_multipliers(orb, n, 1);
    }
    printf("}\n");
  } else if (ana) {
    printf("P(1,%d) orbit, scene %s: WB 11-13 per stop (%d; numbered from 1 "
           "in the scene's order, from 0 in JSON and HDF5)\n", pm,
           vi_scene_name(sc), vi_model_num_stops(m));
    print_stops(orb, m, 0);
    print_multipliers(orb, n, 0);
  }
  if (ana) return 3; /* not P(1,1): a result, not a failure */
  if (pn == 0)
    fprintf(stderr,
            "vibroimpact: energy: the motion is not periodic within the "
            "transient allowed (about %d impacts per forcing period); no P(1,1) "
            "balance\n", pm);
  else
    fprintf(stderr,
            "vibroimpact: energy: the motion is P(%d,%d): period %d forcing "
            "periods with %d impacts; the balance of WB 11-13 needs P(1,1)\n",
            pn, pm, pn, pm);
  return 3;
}

enum { KMAX = 4 }; /* reduced models with the first 1..4 modes */

/* What the P(1,1) report prints, read from the analysed orbit. */
typedef struct balance {
  int n, kmax, tn, tm, by_scan, ok[KMAX], checked, cpn, cpm;
  double T, ph, vN, KE, RE, IE, rr, cl, gmin, rS[KMAX], cv, cg, cp;
  double *FE, *DE, *XE, *reff; /* [n] each */
  const double *om, *ze;
} balance;

static void energy_results(const vi_model *m, const vi_orbit *orb, balance *b)
{
  static const int modes[KMAX] = {0, 1, 2, 3};
  int n = b->n;
  vi_orbit_search_info(orb, &b->tn, &b->tm, &b->by_scan); /* by the direct search? */
  vi_orbit_balance(orb, &b->T, &b->ph, &b->vN, &b->KE, &b->RE, &b->IE, &b->rr, &b->cl);
  vi_orbit_modal_balance(orb, b->FE, b->DE, b->XE, b->reff);
  b->om = vi_model_omega(m);
  b->ze = vi_model_zeta(m);
  b->kmax = n < KMAX ? n : KMAX;
  for (int k = 1; k <= b->kmax; k++)
    b->ok[k - 1] = vi_orbit_reduced_restitution(orb, modes, k, &b->rS[k - 1]) == VI_OK;
  /* check the one-mode reduced model: simulate it with its r_S */
  b->cv = b->cg = b->cp = NAN;
  b->cpn = b->cpm = 0;
  b->checked = n > 1 && b->ok[0] &&
               !reduced_check(m, 1, b->rS[0], &b->cv, &b->cg, &b->cp, &b->cpn, &b->cpm);
  vi_orbit_min_gap(orb, &b->gmin);
}

static void energy_json(const vi_scene *sc, const vi_model *m,
                        const vi_orbit *orb, const balance *b)
{
  printf("{\"scene\": ");
  json_str(vi_scene_name(sc));
  printf(", ");
  vi_app_fe_json(stdout, sc);
  printf("\"P11\": true, \"periodic\": true, \"n\": 1, \"m\": 1, ");
  if (b->by_scan)
    printf("\"found_by\": \"scan\", \"transient_n\": %d, \"transient_m\": %d", b->tn, b->tm);
  else
    printf("\"found_by\": \"transient\"");
  printf(", \"period\": %.17g, \"impact_phase\": %.17g, "
         "\"impact_phase_fraction\": %.17g, "
         "\"vN\": %.17g, \"KE_i\": %.17g, \"RE\": %.17g, \"IE\": %.17g, "
         "\"r\": %.17g, \"r_recovered\": %.17g, \"closure\": %.6g, "
         "\"min_gap\": %.17g, "
         "\"modes\": [",
         b->T, b->ph, b->ph / b->T, b->vN, b->KE, b->RE, b->IE,
         vi_model_restitution(m), b->rr, b->cl, b->gmin);
  for (int j = 0; j < b->n; j++)
    printf("%s{\"omega\": %.17g, \"zeta\": %.17g, \"FE\": %.17g, \"DE\": %.17g, "
           "\"XE\": %.17g, \"r_eff\": %.17g}",
           j ? ", " : "", b->om[j], b->ze[j], b->FE[j], b->DE[j], b->XE[j], b->reff[j]);
  printf("], \"reduced\": [");
  for (int k = 1, first = 1; k <= b->kmax; k++)
    if (b->ok[k - 1]) {
      printf("%s{\"modes\": %d, \"r_S\": %.17g}", first ? "" : ", ", k, b->rS[k - 1]);
      first = 0;
    }
  printf("]");
  print_multipliers(orb, b->n, 1); /* Floquet multipliers (vi_orbit.h) */
  if (b->checked)
    printf(", \"reduced_check\": {\"modes\": 1, \"r_S\": %.17g, \"vN\": %.17g, "
           "\"min_gap\": %.17g, \"impact_phase\": %.17g}",
           b->rS[0], b->cv, b->cg, b->cp);
  printf("}\n");
}

static void energy_text(const vi_scene *sc, const vi_model *m,
                        const vi_orbit *orb, const balance *b)
{
  double T = b->T, ph = b->ph;
  printf("P(1,1) energy balance, scene %s (Wagg & Bishop 2000, eqs. 11-13)\n",
         vi_scene_name(sc));
  if (b->by_scan)
    printf("  (the transient settled on %s; this stable P(1,1) orbit was "
           "found by a scan of impact phases)\n",
           b->tn ? "another motion" : "no periodic motion");
  printf("  period T = %.10g; impact time mod T = %.10g (%.6f T); v_N %.10g\n"
         "  deepest excursion from the stop min(w.x - x_s) over a period "
         "%.6g\n",
         T, ph, ph / T, b->vN, b->gmin);
  printf("  %4s %12s %10s %14s %14s %14s %14s %10s\n", "mode", "omega",
         "zeta", "FE", "DE", "XE", "FE-DE-XE", "r_eff");
  for (int j = 0; j < b->n; j++)
    printf("  %4d %12.6g %10.4g %14.8g %14.8g %14.8g %14.8g %10.5g\n", j + 1,
           b->om[j], b->ze[j], b->FE[j], b->DE[j], b->XE[j],
           b->FE[j] - b->DE[j] - b->XE[j], b->reff[j]);
  printf("  KE_i = %.10g   RE = %.10g   IE = %.10g\n", b->KE, b->RE, b->IE);
  /* r^2 = 1 - RE/KE_i is known to the closure: r = 0 reads sqrt of it */
  double r2 = b->rr * b->rr, rlo = sqrt(fmax(r2 - b->cl, 0.0)), rhi = sqrt(r2 + b->cl);
  printf("  r recovered (WB 12) = %.12f (within [%.12f, %.12f] by the closure)   "
         "(scene r = %g)   closure |RE-IE|/KE_i = %.3g\n",
         b->rr, rlo, rhi, vi_model_restitution(m), b->cl);
  print_multipliers(orb, b->n, 0);
  for (int k = 1; k <= b->kmax; k++) {
    if (b->ok[k - 1])
      printf("  reduced model, first %d mode%s: r_S = %.8f\n", k,
             k > 1 ? "s" : "", b->rS[k - 1]);
    else
      printf("  reduced model, first %d mode%s: no real r_S (RE_S outside "
             "[0, KE_S])\n",
             k, k > 1 ? "s" : "");
  }
  if (b->checked)
    printf("  1-mode model run with r_S: v_N %.8g (full %.8g), deepest "
           "excursion %.6g "
           "(full %.6g), impact time mod T %.6g T (full %.6g T)\n",
           b->cv, b->vN, b->cg, b->gmin, b->cp / T, ph / T);
  else if (b->n > 1 && b->ok[0])
    printf("  1-mode model run with r_S: not P(1,1) (P(%d,%d))\n", b->cpn, b->cpm);
}

int vi_cmd_energy(const app_opts *o)
{
  vi_scene *sc = NULL;
  vi_model *m = NULL;
  vi_orbit *orb = NULL;
  int rc = vi_app_load(o, &sc, &m), pn, pm;
  if (rc) return rc;
  rc = 1;
  balance b;
  memset(&b, 0, sizeof b);
  b.n = vi_model_n(m);
  double *buf = calloc(4 * (size_t)b.n, sizeof(double));
  if (!buf) goto done;
  b.FE = buf;
  b.DE = b.FE + b.n;
  b.XE = b.DE + b.n;
  b.reff = b.XE + b.n;
  if ((rc = energy_scene_ok(sc, m)) || (rc = energy_find(o, m, &orb))) goto done;
  rc = 1;
  /* the file holds what was found, P(1,1) or not */
  if (o->out && write_orbit(o, sc, m, orb)) goto done;
  vi_orbit_classify(orb, &pn, &pm);
  if (pn != 1 || pm != 1) {
    rc = energy_not_p11(o, sc, m, orb, pn, pm);
    goto done;
  }
  energy_results(m, orb, &b);
  if (o->json) energy_json(sc, m, orb, &b);
  else energy_text(sc, m, orb, &b);
  rc = 0;
done:
  free(buf);
  vi_orbit_destroy(&orb);
  vi_model_destroy(&m);
  vi_scene_destroy(&sc);
  return rc;
}
