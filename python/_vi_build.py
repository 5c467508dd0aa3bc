"""cffi (API mode) builder of vibroimpact._vi, the compiled half of the
package: the C declarations Python calls, compiled against the project's
headers and linked to its libraries (libvibroimpact, _scene, _h5).

Run by setup.py (cffi_modules); where the libraries are is decided by
setup.py's find_library() and passed in the environment."""
import os

from cffi import FFI

HERE = os.path.dirname(os.path.abspath(__file__))

CDEF = r"""
typedef int64_t vi_int64;
typedef struct vi_model vi_model;
typedef struct vi_sim vi_sim;
typedef struct vi_scene vi_scene;
typedef struct vi_fe vi_fe;
typedef struct vi_writer vi_writer;
typedef struct vi_sweep vi_sweep;
typedef struct vi_scene_edit vi_scene_edit;
enum vi_status { VI_OK, VI_STOPPED, VI_CANCELLED, VI_ERR_ARG, VI_ERR_DIM,
  VI_ERR_NONFINITE, VI_ERR_NOT_SYMMETRIC, VI_ERR_NOT_SPD, VI_ERR_NOT_PSD,
  VI_ERR_RESTITUTION, VI_ERR_STOP_VECTOR, VI_ERR_FREQUENCY,
  VI_ERR_INITIAL_STATE, VI_ERR_TIME, VI_ERR_TOLERANCE, VI_ERR_STATE,
  VI_ERR_NOMEM, VI_ERR_LAPACK, VI_ERR_INTEGRATOR, VI_ERR_UNSUPPORTED,
  VI_ERR_ROOT, VI_ERR_NOT_CONVERGED, VI_ERR_IO, VI_ERR_PARSE,
  VI_ERR_INVARIANT, VI_ERR_LIMIT, VI_ERR_CALLBACK, ... };
typedef struct vi_diag {
  int code; int line; int column;
  char file[256]; char key[128]; char value[128]; char message[512];
} vi_diag;

const char *vi_status_name(int code);
const char *vi_strerror(int code);
const char *vi_version_string(void);
const char *vi_sundials_version(void);

int vi_model_create(int n, vi_model **out);
void vi_model_destroy(vi_model **model);
int vi_model_create_chain(int n, const double *mass, const double *k,
                          const double *c, vi_model **out);
int vi_model_set_mass(vi_model *m, const double *M, int ldm);
int vi_model_set_damping(vi_model *m, const double *C, int ldc);
int vi_model_set_stiffness(vi_model *m, const double *K, int ldk);
int vi_model_set_forcing(vi_model *m, double omega, const double *a,
                         const double *b, const double *f0);
int vi_model_set_stop(vi_model *m, const double *w, double x_s, double r);
int vi_model_add_stop(vi_model *m, const double *w, double x_s, double r);
int vi_model_num_stops(const vi_model *m);
int vi_model_stop(const vi_model *m, int k, double *w, double *x_s, double *r);
int vi_model_setup(vi_model *m);
const char *vi_model_errmsg(const vi_model *m);
int vi_model_n(const vi_model *m);
int vi_model_bandwidth(const vi_model *m);
double vi_model_omega_forcing(const vi_model *m);
const double *vi_model_omega(const vi_model *m);
const double *vi_model_zeta(const vi_model *m);
const double *vi_model_modal_shapes(const vi_model *m, int *ld);
const double *vi_model_mass(const vi_model *m);
const double *vi_model_damping(const vi_model *m);
const double *vi_model_stiffness(const vi_model *m);
double vi_model_energy(const vi_model *m, const double *x, const double *v);
int vi_model_set_param(vi_model *m, const char *key, double value);
int vi_model_param(const vi_model *m, const char *key, double *value);
int vi_model_copy(const vi_model *m, vi_model **out);
int vi_model_memory_estimate(int n, int kd, int ns, int method, int ledger,
                             vi_int64 *bytes);
int vi_param_kind(const char *key);
int vi_build_cantilever(int modes, double omega1, double zeta, double xi_stop,
                        double *M, double *C, double *K, int ld, double *w,
                        double *gamma);
int vi_build_chain(int n, const double *mass, const double *k,
                   const double *c, double *M, double *C, double *K, int ld);

int vi_sim_create(const vi_model *model, vi_sim **out);
void vi_sim_destroy(vi_sim **sim);
const char *vi_sim_errmsg(const vi_sim *sim);
int vi_sim_set_method(vi_sim *sim, int method);
int vi_sim_set_tolerances(vi_sim *sim, double rtol, double atol);
int vi_sim_set_initial(vi_sim *sim, double t0, const double *x0,
                       const double *v0);
int vi_sim_set_impact_resolution(vi_sim *sim, double ratio);
int vi_sim_set_chatter_threshold(vi_sim *sim, double vmin);
int vi_sim_set_max_step(vi_sim *sim, double hmax);
int vi_sim_method_used(const vi_sim *sim);
const char *vi_sim_method_note(const vi_sim *sim);
int vi_sim_state(const vi_sim *sim, double *t, double *x, double *v);
vi_int64 vi_sim_stat(const vi_sim *sim, int which);
const char *vi_stat_name(int which);
const char *vi_method_name(int method);
int vi_method_from_name(const char *name);
int vi_sim_ledger(const vi_sim *sim, double *E, double *FE, double *DE,
                  double *XE, double *CE, double *dE, double *ie);
double vi_sim_ledger_max_residual(const vi_sim *sim);
int vi_sim_stop_losses(const vi_sim *sim, double *ie);
int vi_sim_add_spring(vi_sim *sim, int type, int i, int j, double k,
                      double gap);

int vi_scene_load_limited(const char *path, vi_int64 max_bytes, int max_depth,
                          vi_scene **out, vi_diag *diag);
int vi_scene_load_within(const char *path, vi_int64 max_bytes, int max_depth,
                         double max_memory, vi_scene **out, vi_diag *diag);
int vi_scene_parse(const char *text, vi_int64 len, const char *name,
                   vi_scene **out, vi_diag *diag);
void vi_scene_destroy(vi_scene **scene);
int vi_scene_create_model(const vi_scene *sc, vi_model **out, vi_diag *diag);
int vi_scene_create_fe(const vi_scene *sc, int modes, int keep, vi_fe **out,
                       vi_diag *diag);
int vi_scene_check_memory(const vi_scene *sc, double max_bytes, vi_diag *diag);
double vi_scene_memory_available(void);
int vi_scene_configure_sim(const vi_scene *sc, vi_sim *sim, vi_diag *diag);
const char *vi_scene_name(const vi_scene *sc);
const char *vi_scene_text(const vi_scene *sc);
int vi_scene_n(const vi_scene *sc);
int vi_scene_dofs(const vi_scene *sc);
int vi_scene_initial(const vi_scene *sc, double *x0, double *v0);
double vi_scene_t0(const vi_scene *sc);
double vi_scene_t_end(const vi_scene *sc);
double vi_scene_rtol(const vi_scene *sc);
double vi_scene_atol(const vi_scene *sc);
int vi_scene_method(const vi_scene *sc);
int vi_scene_samples_per_period(const vi_scene *sc);
int vi_scene_outputs(const vi_scene *sc);
int vi_scene_set_run(vi_scene *sc, double rtol, double atol, double periods,
                     int method);
void vi_diag_format(const vi_diag *d, char *buf, int len);
const char *vi_scene_default_text(void);
int vi_scene_param_key(const vi_scene *sc, const char *key, char *out,
                       int len, vi_diag *diag);
int vi_scene_edit_create(const char *text, vi_int64 len, const char *name,
                         vi_scene_edit **out, vi_diag *diag);
void vi_scene_edit_destroy(vi_scene_edit **e);
int vi_scene_edit_assign(vi_scene_edit *e, const char *assignment,
                         vi_diag *diag);
int vi_scene_edit_parse(const vi_scene_edit *e, vi_scene **out,
                        vi_diag *diag);
int vi_scene_edit_parse_within(const vi_scene_edit *e, double max_memory,
                               vi_scene **out, vi_diag *diag);

int vi_fe_create(int n, vi_fe **out);
void vi_fe_destroy(vi_fe **fe);
const char *vi_fe_errmsg(const vi_fe *fe);
int vi_fe_set_mass_csc(vi_fe *fe, int storage, int base, const int *colptr,
                       const int *rowind, const double *values);
int vi_fe_set_stiffness_csc(vi_fe *fe, int storage, int base,
                            const int *colptr, const int *rowind,
                            const double *values);
int vi_fe_set_damping_csc(vi_fe *fe, int storage, int base,
                          const int *colptr, const int *rowind,
                          const double *values);
int vi_fe_set_rayleigh(vi_fe *fe, double alpha, double beta);
int vi_fe_set_modal_damping(vi_fe *fe, int nzeta, const double *zeta);
int vi_fe_set_modes(vi_fe *fe, int k);
int vi_fe_set_rigid_modes(vi_fe *fe, int count);
int vi_fe_set_accuracy(vi_fe *fe, double tol);
int vi_fe_add_stop(vi_fe *fe, const double *w, double x_s, double r);
int vi_fe_add_stop_dof(vi_fe *fe, int dof, int direction, double x_s,
                       double r);
int vi_fe_set_forcing(vi_fe *fe, double omega, const double *a,
                      const double *b, const double *f0);
int vi_fe_set_keep_shapes(vi_fe *fe, int keep);
int vi_fe_setup(vi_fe *fe);
int vi_fe_create_model(const vi_fe *fe, vi_model **out);
int vi_fe_n(const vi_fe *fe);
int vi_fe_num_modes(const vi_fe *fe);
const double *vi_fe_omega(const vi_fe *fe);
const double *vi_fe_shapes(const vi_fe *fe, int *ld);
double vi_fe_residual(const vi_fe *fe);
int vi_fe_summary(const vi_fe *fe, int *massless, int *rigid, int *rule,
                  double *orthogonality);
int vi_fe_to_modal(const vi_fe *fe, const double *x, double *q);

int vi_writer_create(const char *path, const vi_model *model, int compress,
                     vi_writer **out, vi_diag *diag);
int vi_writer_write_header(vi_writer *w, const vi_scene *scene, double rtol,
                           double atol, int method);
int vi_writer_run_info(vi_writer *w, const vi_sim *sim);
int vi_writer_finish(vi_writer *w, int complete);
void vi_writer_abort(vi_writer **w);
const char *vi_writer_errmsg(const vi_writer *w);

typedef struct vi_py_run vi_py_run;
vi_py_run *vi_py_run_new(int n, int states);
void vi_py_run_free(vi_py_run *r);
int vi_py_nomem(const vi_py_run *r);
void vi_py_sim_free(vi_sim *sim);
int vi_py_prepare(vi_py_run *r, vi_sim *sim, int method, double rtol,
                  double atol, double dt, int ledger);
const double *vi_py_table(const vi_py_run *r, int which, vi_int64 *rows,
                          int *width);
int vi_py_replay(const vi_py_run *r, vi_writer *w);
int vi_py_sim_run(vi_sim *sim, vi_py_run *r, double t_end, int *interrupted);
int vi_py_sigint_arm(void);
void vi_py_sigint_disarm(void);
unsigned vi_py_sigint_count(void);
int vi_py_cancel_since(void *user);
double vi_py_bench_simulate(const vi_model *model, int reps, double t_end,
                            int method, double rtol, double atol);
double vi_py_bench_sweep(const vi_model *model, const char *key,
                         const double *values, int nv, int transient,
                         int record, int method, double *sink);
"""

STUDY_CDEF_FILE = os.path.join(HERE, "src", "vi_py_study.cdef")


def make_builder(include_dirs, library_dirs):
    ffi = FFI()
    cdef = CDEF
    if os.path.exists(STUDY_CDEF_FILE):
        with open(STUDY_CDEF_FILE) as f:
            cdef += f.read()
    ffi.cdef(cdef)
    ffi.set_source(
        "vibroimpact._vi",
        '#include "vi_py.h"\n'
        "typedef int64_t vi_int64;\n"
        '#include <vibroimpact/vi_scene.h>\n'
        '#include <vibroimpact/vi_scene_param.h>\n'
        '#include <vibroimpact/vi_scene_edit.h>\n'
        '#include <vibroimpact/vi_writer.h>\n',
        sources=[os.path.join("src", "vi_py.c"), os.path.join("src", "vi_py_bench.c")],
        include_dirs=[os.path.join(HERE, "src")] + include_dirs,
        library_dirs=library_dirs,
        runtime_library_dirs=library_dirs,
        libraries=["vibroimpact_h5", "vibroimpact_scene", "vibroimpact"],
        extra_compile_args=["-O2", "-Wall", "-Wextra", "-Wno-unused-parameter"],
    )
    return ffi


def _from_env():
    inc = [p for p in os.environ.get("VI_PY_INCLUDE", "").split(os.pathsep) if p]
    lib = [p for p in os.environ.get("VI_PY_LIBDIR", "").split(os.pathsep) if p]
    return make_builder(inc, lib)


ffibuilder = _from_env()

if __name__ == "__main__":
    ffibuilder.compile(verbose=True)
