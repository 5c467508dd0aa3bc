/* Outside consumer: the Fig. 2 chain's modes and impact count through an
 * installed vibroimpact.  Prints "ok" and exits 0 when the values hold. */
#include <math.h>
#include <stdio.h>

#include <vibroimpact.h>

static int count(const vi_event *ev, void *user)
{
  if (ev->kind == VI_EVENT_IMPACT) ++*(int *)user;
  return 0;
}

int main(void)
{
  const double mass[2] = {1, 1}, k[2] = {1, 1}, c[2] = {0.1, 0.1};
  const double a[2] = {0.5, 0}, w[2] = {0, 1};
  double M[4], C[4], K[4];
  vi_model *m = NULL;
  vi_sim *s = NULL;
  int impacts = 0;
  if (vi_version_number() != VI_VERSION_NUMBER) return 1;
  vi_build_chain(2, mass, k, c, M, C, K, 2);
  if (vi_model_create(2, &m) || vi_model_set_mass(m, M, 2) ||
      vi_model_set_damping(m, C, 2) || vi_model_set_stiffness(m, K, 2) ||
      vi_model_set_forcing(m, 0.9, a, NULL, NULL) ||
      vi_model_set_stop(m, w, 0.1, 0.7) || vi_model_setup(m))
    return 1;
  double w1 = vi_model_omega(m)[0];
  if (fabs(w1 - (sqrt(5.0) - 1) / 2) > 1e-14) return 1;
  if (vi_sim_create(m, &s) || vi_sim_set_event_callback(s, count, &impacts, NULL) ||
      vi_sim_run(s, 100 * 2 * acos(-1.0) / 0.9))
    return 1;
  vi_sim_destroy(&s);
  vi_model_destroy(&m);
  printf("%s: omega_1 = %.15f, %d impacts\n", impacts == 100 ? "ok" : "FAIL", w1, impacts);
  return impacts == 100 ? 0 : 1;
}
