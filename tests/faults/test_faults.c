/* test_faults.c - the program under faults and hostile input (ctest label
 * `faults`): a full disk, unwritable and non-regular outputs, signals in
 * every phase, standard output on /dev/full, huge and deep scenes, values
 * outside the range where the numerics make sense.  Each case asserts the
 * exit status, the message, and what is and is not on disk.
 *
 *   test_faults PATH-TO-vibroimpact PATH-TO-libvi_enospc.so */
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mount.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <hdf5.h>

#include "vi_testutil.h"

static const char *app, *hook;
static char dir[] = "/tmp/vi_test_faults_XXXXXX";
static char errbuf[65536];

static double now(void)
{
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

/* dir/name, kept for the whole run (freed at the end of main) */
static char *paths[256];
static int npaths;
static char *path(const char *name)
{
  for (int k = 0; k < npaths; k++)
    if (!strcmp(paths[k] + strlen(dir) + 1, name)) return paths[k];
  char buf[600];
  snprintf(buf, sizeof buf, "%s/%s", dir, name);
  assert_true(npaths < 256);
  char *p = strdup(buf);
  assert_non_null(p);
  return paths[npaths++] = p;
}

static int exists(const char *p)
{
  struct stat st;
  return lstat(p, &st) == 0;
}

static void write_file(const char *p, const char *text)
{
  FILE *f = fopen(p, "w");
  assert_non_null(f);
  fputs(text, f);
  assert_int_equal(fclose(f), 0);
}

static char *slurp(const char *p)
{
  FILE *f = fopen(p, "rb");
  if (!f) {
    errbuf[0] = '\0';
    return errbuf;
  }
  size_t n = fread(errbuf, 1, sizeof errbuf - 1, f);
  errbuf[n] = '\0';
  fclose(f);
  return errbuf;
}

/* Start the app with argv; stdout to out_path (NULL: a file in dir),
 * stderr to dir/stderr; env_extra (NULL or "NAME=VALUE") added. */
static const char *env_extra3; /* a third NAME=VALUE for the next start */
static long fsize_limit; /* > 0: RLIMIT_FSIZE of the next start, SIGXFSZ ignored */
static long cpu_limit;   /* > 0: RLIMIT_CPU (s) of the next start: a hang bound */
static pid_t start(char *const argv[], const char *out_path,
                   const char *env_extra, const char *env_extra2)
{
  pid_t pid = fork();
  assert_true(pid >= 0);
  if (pid == 0) {
    int e = open(path("stderr"), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (out_path && !strcmp(out_path, "closed")) {
      close(1); /* `>&-` */
    } else {
      int o = open(out_path ? out_path : path("stdout"),
                   O_WRONLY | O_CREAT | O_TRUNC, 0644);
      dup2(o, 1);
      close(o);
    }
    dup2(e, 2);
    close(e);
    if (env_extra) putenv((char *)env_extra);
    if (env_extra2) putenv((char *)env_extra2);
    if (env_extra3) putenv((char *)env_extra3);
    if (fsize_limit > 0) { /* writes past it fail with EFBIG, as on a full disk */
      struct rlimit rl = {(rlim_t)fsize_limit, (rlim_t)fsize_limit};
      signal(SIGXFSZ, SIG_IGN);
      if (setrlimit(RLIMIT_FSIZE, &rl) != 0) _exit(126);
    }
    if (cpu_limit > 0) {
      struct rlimit rl = {(rlim_t)cpu_limit, (rlim_t)cpu_limit};
      if (setrlimit(RLIMIT_CPU, &rl) != 0) _exit(126);
    }
    execv(app, argv);
    _exit(127);
  }
  return pid;
}

/* Wait up to 120 s; exit status or 128 + signal. */
static int finish(pid_t pid)
{
  int st;
  for (int i = 0; i < 120000; i++) {
    pid_t r = waitpid(pid, &st, WNOHANG);
    if (r == pid) return WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
    usleep(1000);
  }
  kill(pid, SIGKILL);
  waitpid(pid, &st, 0);
  fail_msg("the program did not end within 120 s");
  return -1;
}

static int run(char *const argv[], const char *out_path)
{
  return finish(start(argv, out_path, NULL, NULL));
}

#define ARGV(...) ((char *const[]){(char *)app, __VA_ARGS__, NULL})

static const char *CHAIN2 =
    "model:\n  chain: {n: 2, m: 1, k: 1, c: 0.1}\n"
    "stop: {mass: 2, xs: 0.1, r: 0.7}\n";

static void expect(int rc, int want, const char *msg)
{
  char *err = slurp(path("stderr"));
  if (rc != want || (msg && !strstr(err, msg)))
    print_error("exit %d (want %d), stderr: %s\n", rc, want, err);
  assert_int_equal(rc, want);
  if (msg) assert_non_null(strstr(err, msg));
}

/* ---- full disk ------------------------------------------------------------ */
/* The disk fills during the run: exit 1 with a message, no crash, the old
 * file intact, no partial file. */
static void full_disk_case(const char *out, const char *env, const char *env2)
{
  char part[600];
  snprintf(part, sizeof part, "%s.part", out);
  write_file(out, "old contents\n");
  int rc = finish(start(ARGV("--periods", "100", "-o", (char *)out, "--quiet"),
                        NULL, env, env2));
  expect(rc, 1, "No space left on device");
  assert_string_equal(slurp(out), "old contents\n");
  assert_false(exists(part));
}

static void test_full_disk(void **state)
{
  (void)state;
  char *mnt = path("small");
  assert_int_equal(mkdir(mnt, 0755), 0);
  int mounted = geteuid() == 0 &&
                mount("tmpfs", mnt, "tmpfs", 0, "size=200k") == 0;
  if (mounted) {
    print_message("full disk: a 200 KiB tmpfs\n");
    char out[600];
    snprintf(out, sizeof out, "%s/out.h5", mnt);
    for (int k = 0; k < 4; k++) full_disk_case(out, NULL, NULL);
    /* the CSV too */
    snprintf(out, sizeof out, "%s/imp.csv", mnt);
    char big[600];
    snprintf(big, sizeof big, "%s/filler", mnt);
    int fd = open(big, O_WRONLY | O_CREAT, 0644);
    char block[4096] = {0};
    while (write(fd, block, sizeof block) > 0) {
    }
    close(fd);
    unlink(big); /* free again: now a 4 KiB budget is what is left */
    fd = open(big, O_WRONLY | O_CREAT, 0644);
    for (int k = 0; k < 48 && write(fd, block, sizeof block) > 0; k++) {
    }
    close(fd);
    write_file(out, "old\n");
    int rc = run(ARGV("--periods", "2000", "--impacts-csv", out, "--quiet"), NULL);
    expect(rc, 1, "cannot write");
    assert_string_equal(slurp(out), "old\n");
    assert_false(exists(path("small/imp.csv.part")));
    assert_int_equal(umount(mnt), 0);
  } else {
    print_message("full disk: LD_PRELOAD hook (cannot mount here)\n");
  }
  /* the hook as well, so both paths are exercised where possible */
  char env[700];
  snprintf(env, sizeof env, "LD_PRELOAD=%s", hook);
  full_disk_case(path("hooked.h5"), env, "VI_FAULT_BUDGET=150000");
  /* a file system without fallocate: the writer reserves with zeros */
  env_extra3 = "VI_FAULT_NO_FALLOCATE=1";
  full_disk_case(path("hooked.h5"), env, "VI_FAULT_BUDGET=150000");
  int rc = finish(start(ARGV("--periods", "3", "-o", path("nofalloc.h5"), "--quiet"),
                        NULL, env, NULL));
  env_extra3 = NULL;
  expect(rc, 0, NULL);
  hid_t f = H5Fopen(path("nofalloc.h5"), H5F_ACC_RDONLY, H5P_DEFAULT);
  assert_true(f >= 0); /* a valid file, padding or not */
  hid_t ds = H5Dopen2(f, "impacts/time", H5P_DEFAULT), sp = H5Dget_space(ds);
  hsize_t ni = 0;
  H5Sget_simple_extent_dims(sp, &ni, NULL);
  H5Sclose(sp);
  H5Dclose(ds);
  H5Fclose(f);
  assert_true(ni >= 3);
  remove(path("nofalloc.h5"));
  rmdir(mnt);
  remove(path("hooked.h5"));
}

/* ---- outputs that are not ours to replace ------------------------------- */
static void test_non_regular_outputs(void **state)
{
  (void)state;
  /* checked before anything else: the missing scene is never read */
  char *fifo = path("fifo");
  assert_int_equal(mkfifo(fifo, 0644), 0);
  const char *targets[3] = {"/dev/null", fifo, dir};
  const char *kinds[3] = {"a character device", "a FIFO", "a directory"};
  for (int k = 0; k < 3; k++) {
    int rc = run(ARGV("no-such-scene.yaml", "-o", (char *)targets[k]), NULL);
    expect(rc, 1, kinds[k]);
    /* a CSV stream may go to a character device: written, not replaced */
    rc = run(ARGV(k ? "no-such-scene.yaml" : "--quiet", "--impacts-csv",
                  (char *)targets[k]), NULL);
    expect(rc, k ? 1 : 0, k ? kinds[k] : NULL);
    char part[600];
    snprintf(part, sizeof part, "%s.part", targets[k]);
    assert_false(exists(part));
  }
  struct stat st;
  assert_int_equal(stat("/dev/null", &st), 0);
  assert_true(S_ISCHR(st.st_mode)); /* still a device */
  assert_int_equal(lstat(fifo, &st), 0);
  assert_true(S_ISFIFO(st.st_mode));
  /* a link to a device is refused the same way */
  char *ln = path("to-null.h5");
  assert_int_equal(symlink("/dev/null", ln), 0);
  expect(run(ARGV("--periods", "1", "-o", ln), NULL), 1, "a character device");
  /* a link to a regular file is written through: the link stays */
  char *real = path("real.h5"), *ln2 = path("link.h5");
  assert_int_equal(symlink("real.h5", ln2), 0);
  expect(run(ARGV("--periods", "1", "-o", ln2, "--quiet"), NULL), 0, NULL);
  assert_int_equal(lstat(ln2, &st), 0);
  assert_true(S_ISLNK(st.st_mode));
  hid_t f = H5Fopen(real, H5F_ACC_RDONLY, H5P_DEFAULT);
  assert_true(f >= 0);
  H5Fclose(f);
  /* a planted PATH.part link is not followed */
  char *victim = path("victim"), *out = path("planted.h5");
  write_file(victim, "precious\n");
  char part[600];
  snprintf(part, sizeof part, "%s.part", out);
  assert_int_equal(symlink(victim, part), 0);
  expect(run(ARGV("--periods", "1", "-o", out), NULL), 1, "symbolic link");
  assert_string_equal(slurp(victim), "precious\n");
  assert_false(exists(out));
  /* an unwritable place: exit 1 before computing, nothing created */
  expect(run(ARGV("no-such-scene.yaml", "-o", "/proc/vi_out.h5"), NULL), 1,
         "/proc/vi_out.h5");
  if (geteuid() == 0) {
    char *ro = path("ro");
    assert_int_equal(mkdir(ro, 0755), 0);
    if (mount("tmpfs", ro, "tmpfs", MS_RDONLY, "size=64k") == 0) {
      char o[600];
      snprintf(o, sizeof o, "%s/x.h5", ro);
      expect(run(ARGV("no-such-scene.yaml", "-o", o), NULL), 1,
             "Read-only file system");
      umount(ro);
    }
    rmdir(ro);
  }
  unlink(fifo);
  unlink(ln);
  unlink(ln2);
  unlink(real);
  unlink(part);
  unlink(victim);
}

/* ---- standard output on a full device ----------------------------------- */
static void test_stdout_full(void **state)
{
  (void)state;
  if (access("/dev/full", W_OK) != 0) skip();
  const char *msg = "cannot write the standard output";
  expect(run(ARGV("--periods", "2"), "/dev/full"), 1, msg);
  expect(run(ARGV("--periods", "2", "--impacts-csv", "-", "--quiet"), "/dev/full"), 1, msg);
  expect(run(ARGV("energy", "--json"), "/dev/full"), 1, msg);
  expect(run(ARGV("energy"), "/dev/full"), 1, msg);
  expect(run(ARGV("restitution", "--re", "0.5", "--ke", "1"), "/dev/full"), 1, msg);
  expect(run(ARGV("--help"), "/dev/full"), 1, msg);
  expect(run(ARGV("--version"), "/dev/full"), 1, msg);
  /* stdout closed: the output file does not inherit descriptor 1, so the
   * summary cannot land in it; its loss is reported */
  char *h5 = path("closed.h5");
  for (int quiet = 0; quiet < 2; quiet++) {
    expect(run(ARGV("--periods", "2", "-o", h5, quiet ? "--quiet" : "--rtol",
                    quiet ? "--quiet" : "1e-8"), "closed"),
           quiet ? 0 : 1, quiet ? NULL : msg);
    hid_t f = H5Fopen(h5, H5F_ACC_RDONLY, H5P_DEFAULT); /* whole, valid */
    assert_true(f >= 0);
    int complete = -1;
    hid_t a = H5Aopen(f, "complete", H5P_DEFAULT);
    H5Aread(a, H5T_NATIVE_INT, &complete);
    H5Aclose(a);
    H5Fclose(f);
    assert_int_equal(complete, 1);
    remove(h5);
  }
}

/* ---- signals in every phase ---------------------------------------------- */
/* CPU seconds the process has used (user + system, /proc/PID/stat's
 * fields 14 and 15, in clock ticks), or -1 once it cannot be read. */
static double cpu_of(pid_t pid)
{
  char p[64], buf[1024];
  snprintf(p, sizeof p, "/proc/%d/stat", (int)pid);
  FILE *f = fopen(p, "r");
  size_t n = f ? fread(buf, 1, sizeof buf - 1, f) : 0;
  if (f) fclose(f);
  buf[n] = '\0';
  const char *s = strrchr(buf, ')'); /* the command name may hold spaces */
  if (!s) return -1.0;
  /* the space before each field from 3 (the state) to 14 (utime) */
  for (int field = 3; field <= 14 && s; field++) s = strchr(s + 1, ' ');
  if (!s) return -1.0;
  char *end;
  unsigned long ut = strtoul(s, &end, 10), st = strtoul(end, &end, 10);
  if (*end != ' ') return -1.0;
  return (double)(ut + st) / (double)sysconf(_SC_CLK_TCK);
}

/* Start, wait until the process has used `work` CPU seconds (it must
 * still be running: it is in the phase), signal, and return the exit
 * status; prints the response time.  The wait counts the child's CPU, not
 * the clock: a loaded machine (or a sanitized build) slows the start and
 * the set-up before the phase as much as the clock, so a fixed delay
 * signalled some runs before the phase began, where the program's words
 * differ (c0143d9; one loaded run in about ten at 0.3 s).  Each phase has
 * seconds of work past its first 0.2 CPU-s. */
static int signal_in(const char *what, char *const argv[], double work, int sig)
{
  pid_t pid = start(argv, NULL, NULL, NULL);
  double c = 0.0, w0 = now();
  int st;
  while ((c = cpu_of(pid)) < work && c >= 0.0 && now() - w0 < 120.0 &&
         waitpid(pid, &st, WNOHANG) == 0)
    usleep(2000);
  assert_int_equal(waitpid(pid, &st, WNOHANG), 0); /* still in the phase */
  assert_true(c >= work);
  double t0 = now();
  kill(pid, sig);
  int rc = finish(pid);
  print_message("%-34s %s after %.2f CPU-s, answered in %.3f s, exit %d\n", what,
                sig == SIGINT ? "SIGINT " : "SIGTERM", c, now() - t0, rc);
  return rc;
}

static void test_signals(void **state)
{
  (void)state;
  /* parsing: a deep file with the depth limit lifted (seconds of work) */
  char *deep = path("deep.yaml");
  FILE *f = fopen(deep, "w");
  fputs("a: ", f);
  for (int k = 0; k < 20000; k++) fputs("{a: ", f);
  fputs("1", f);
  for (int k = 0; k < 20000; k++) fputc('}', f);
  fputc('\n', f);
  fclose(f);
  char *h5 = path("sig.h5"), part[600];
  snprintf(part, sizeof part, "%s.part", h5);
  int rc = signal_in("parsing (20000 levels)",
                     ARGV(deep, "--max-depth", "1000000", "-o", h5), 0.2, SIGINT);
  assert_int_equal(rc, 130);
  assert_false(exists(h5));
  assert_false(exists(part));
  /* building the model: eigen-solve of a 2500-mass chain (the exact
   * method needs its modes: dense storage) */
  char *chain = path("chain.yaml");
  write_file(chain, "model:\n  chain: {n: 2500, m: 1, k: 1, c: 0.1}\n"
                    "stop: {mass: 1, xs: 0.1, r: 0.7}\n"
                    "forcing: {omega: 0.9, on: [1], amplitude: 0.5}\n"
                    "run: {periods: 1, method: exact}\n");
  rc = signal_in("building the model (n = 2500)", ARGV(chain, "-o", h5), 0.2,
                 SIGTERM);
  assert_int_equal(rc, 143);
  assert_false(exists(h5));
  assert_false(exists(part));
  /* running: Omega = 1e-6, one forcing period is 6.3e6 time units; the
   * file is valid and marked incomplete */
  char *slow = path("slow.yaml");
  char text[512];
  snprintf(text, sizeof text, "%sforcing: {omega: 1.0e-6, a: [0.5, 0]}\n"
           "run: {periods: 10}\n", CHAIN2);
  write_file(slow, text);
  const char *methods[3] = {"adams", "exact", "auto"};
  for (int k = 0; k < 3; k++) {
    int sig = k == 1 ? SIGTERM : SIGINT;
    char what[64];
    snprintf(what, sizeof what, "running (Omega 1e-6, %s)", methods[k]);
    rc = signal_in(what, ARGV(slow, "--method", (char *)methods[k], "-o", h5,
                              "--quiet"), 0.2, sig);
    assert_int_equal(rc, 128 + sig);
    assert_non_null(strstr(slurp(path("stderr")), "marked incomplete"));
    assert_false(exists(part));
    hid_t fh = H5Fopen(h5, H5F_ACC_RDONLY, H5P_DEFAULT);
    assert_true(fh >= 0);
    int complete = -1;
    hid_t a = H5Aopen(fh, "complete", H5P_DEFAULT);
    H5Aread(a, H5T_NATIVE_INT, &complete);
    H5Aclose(a);
    H5Fclose(fh);
    assert_int_equal(complete, 0);
    remove(h5);
  }
  /* the energy analysis: no file until the orbit is found */
  rc = signal_in("energy (Omega 1e-6)", ARGV("energy", slow, "-o", h5), 0.2,
                 SIGINT);
  assert_int_equal(rc, 130);
  assert_false(exists(h5));
  assert_false(exists(part));
  remove(deep);
  remove(chain);
  remove(slow);
}

/* ---- huge and deep scenes, memory ---------------------------------------- */
static void test_limits(void **state)
{
  (void)state;
  char *h5 = path("lim.h5");
  expect(run(ARGV("/dev/zero", "-o", h5), NULL), 2, "larger than 16777216 bytes");
  assert_false(exists(h5));
  expect(run(ARGV("/dev/zero", "--max-scene-size", "1K"), NULL), 2,
         "larger than 1024 bytes");
  /* the limit holds with --set too (the scene is then read for editing) */
  expect(run(ARGV("/dev/zero", "--max-scene-size", "1K", "--set", "stop.r=0.6", "-o", h5),
             NULL), 2, "larger than 1024 bytes");
  assert_false(exists(h5));
  /* nesting: refused at the limit, named */
  char *deep = path("deep.yaml");
  FILE *f = fopen(deep, "w");
  fputs("a: ", f);
  for (int k = 0; k < 100000; k++) fputc('[', f);
  for (int k = 0; k < 100000; k++) fputc(']', f);
  fputc('\n', f);
  fclose(f);
  expect(run(ARGV(deep), NULL), 2, "nesting deeper than 32 levels");
  expect(run(ARGV(deep, "--max-depth", "40"), NULL), 2,
         "nesting deeper than 40 levels");
  /* memory: a 20000-mass chain with its modes (the ledger asks for them)
   * needs ~51 GB dense; without, band storage takes a few MB and runs; a
   * tiny allowance refuses Fig. 2's chain, naming the key and both figures */
  char *chain = path("chain.yaml");
  write_file(chain, "model:\n  chain: {n: 20000, m: 1, k: 1, c: 0.1}\n"
                    "stop: {mass: 1, xs: 0.1, r: 0.7}\n"
                    "forcing: {omega: 0.9, on: [1], amplitude: 0.5}\n"
                    "output: {ledger: true}\n");
  expect(run(ARGV(chain, "--max-memory", "4G"), NULL), 2,
         "model.chain.n = 20000: the model would need about");
  write_file(chain, "model:\n  chain: {n: 20000, m: 1, k: 1, c: 0.1}\n"
                    "stop: {mass: 1, xs: 0.1, r: 0.7}\n"
                    "forcing: {omega: 0.9, on: [1], amplitude: 0.5}\n"
                    "run: {t_end: 2}\n");
  expect(run(ARGV(chain, "--max-memory", "100M", "--quiet"), NULL), 0, NULL);
  char fig2[600];
  snprintf(fig2, sizeof fig2, "%s/fig2.yaml", VI_SCENE_DIR);
  expect(run(ARGV(fig2, "--max-memory", "1K"), NULL), 2, "model.chain.n = 2");
  /* an alias bomb: 140 kB asking for a 20000 x 20000 K by repeating one
   * row (9.6 GB): refused before any n x n storage exists */
  f = fopen(chain, "w");
  fputs("initial: {x: &r [1", f);
  for (int k = 1; k < 20000; k++) fputs(", 0", f);
  fputs("]}\nmodel:\n  K: [*r", f);
  for (int k = 1; k < 20000; k++) fputs(", *r", f);
  fputs("]\nstop: {mass: 1, xs: 0.1, r: 0.5}\nrun: {t_end: 1}\n", f);
  fclose(f);
  expect(run(ARGV(chain), NULL), 2, "model.K: an n x n matrix needs its n^2 numbers");
  remove(deep);
  remove(chain);
  /* studies: the memory a sweep or basins plans, refused before it is
   * allocated (10^7 points x 100 periods x 4 doubles: 30 GB of strobes) */
  expect(run(ARGV("sweep", fig2, "--param", "forcing.omega", "--from", "0.8",
                  "--to", "1", "--steps", "10000", "--param2", "forcing.a[1]",
                  "--from2", "0.1", "--to2", "0.5", "--steps2", "1000", "--record",
                  "100", "--max-memory", "16G", "-o", h5), NULL),
         2, "--steps 10000 x --steps2 1000 x --record 100 (2 coordinates, -o) "
            "would need about");
  assert_non_null(strstr(slurp(path("stderr")), "(3.05e+04 MB of stroboscopic states)"));
  assert_non_null(strstr(slurp(path("stderr")), "more than the 1.64e+04 MB allowed"));
  assert_false(exists(h5));
  /* the same without --max-memory: more than any machine this runs on */
  expect(run(ARGV("sweep", fig2, "--param", "forcing.omega", "--from", "0.8",
                  "--to", "1", "--steps", "100000", "--param2", "forcing.a[1]",
                  "--from2", "0.1", "--to2", "0.5", "--steps2", "100000", "--record",
                  "100"), NULL), 2, "available to this process");
  expect(run(ARGV("basins", fig2, "--param", "initial.x[2]", "--from", "-1", "--to",
                  "0.09", "--steps", "1000", "--param2", "initial.v[2]", "--from2",
                  "-1", "--to2", "1", "--steps2", "1000", "--max-memory", "100M"),
             NULL), 2, "basins) would need about");
  /* orbits: the model's own estimate, as for run */
  write_file(chain, "model:\n  chain: {n: 100000, m: 1, k: 1, c: 0.1}\n"
                    "stop: {mass: 1, xs: 0.1, r: 0.7}\n"
                    "forcing: {omega: 0.9, on: [1], amplitude: 0.5}\n"
                    "run: {method: exact}\n");
  expect(run(ARGV("orbits", chain), NULL), 2, "model.chain.n = 100000");
  assert_non_null(strstr(slurp(path("stderr")), "the model would need about"));
  remove(chain);
}

/* ---- values the numerics cannot honour: exit 2 naming the key ----------- */
static void test_ranges(void **state)
{
  (void)state;
  static const struct {
    const char *yaml, *key;
  } cases[] = {
      {"forcing: {omega: 0.9, a: [0.5, 0]}\nrun: {rtol: 10}\n", "run.rtol"},
      {"forcing: {omega: 0.9, a: [0.5, 0]}\nrun: {rtol: 1}\n", "run.rtol"},
      {"forcing: {omega: 0.9, a: [0.5, 0]}\nrun: {atol: 1e10}\n", "run.atol"},
      {"forcing: {omega: 1e-300, a: [0.5, 0]}\n", "forcing.omega"},
      {"forcing: {omega: 1e300, a: [0.5, 0]}\n", "forcing.omega"},
      {"forcing: {omega: -0.9, a: [0.5, 0]}\n", "forcing.omega"},
      {"forcing: {omega: 0.9, a: [1e300, 0]}\n", "forcing.a[1]"},
      {"forcing: {omega: 0.9, a: [0.5, 0]}\nrun: {periods: 1e-300}\n", "run.periods"},
      {"forcing: {omega: 0.9, a: [0.5, 0]}\nrun: {periods: 1e300}\n", "run.periods"},
      {"forcing: {omega: 0.9, a: [0.5, 0]}\ninitial: {v: [1e30, 0]}\n", "initial.v"},
      {"forcing: {omega: 0.9, a: [0.5, 0]}\ninitial: {x: [-1e300, 0]}\n", "initial.x[1]"},
      {"forcing: {omega: !!str 0.9, a: [0.5, 0]}\n", "forcing.omega"},
      {"forcing: {omega: '0.9', a: [0.5, 0]}\n", "forcing.omega"},
      {"forcing: {omega: 0.9, a: [0.5, 0]}\nname: [1, 2]\n", "name"},
      {"forcing: {omega: 0.9, a: [0.5, 0]}\n---\nname: second\n", "second YAML document"},
      {"forcing: {omega: 0.9, a: [0.5, 0]}\noutput: {ledger: 'true'}\n", "output.ledger"},
  };
  char *scene = path("range.yaml"), *h5 = path("range.h5");
  for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
    char text[1024];
    snprintf(text, sizeof text, "%s%s", CHAIN2, cases[k].yaml);
    write_file(scene, text);
    expect(run(ARGV(scene, "--method", "exact", "-o", h5), NULL), 2, cases[k].key);
    assert_false(exists(h5));
  }
  /* masses, stiffnesses and damping far apart */
  static const char *models[][2] = {
      {"model:\n  chain: {n: 2, m: [1, 1e-30], k: 1, c: 0.1}\n", "model.chain.m"},
      {"model:\n  chain: {n: 2, m: 1, k: [1e30, 1], c: 0.1}\n", "model.chain.k"},
      {"model:\n  chain: {n: 2, m: 1, k: 1, c: 1e300}\n", "model.chain.c"},
      {"model:\n  chain: {n: 2, m: 1, k: 1, c: 1e20}\n", "damping ratio"},
  };
  for (size_t k = 0; k < sizeof models / sizeof models[0]; k++) {
    char text[1024];
    snprintf(text, sizeof text, "%sstop: {mass: 2, xs: 0.1, r: 0.7}\n"
             "forcing: {omega: 0.9, a: [0.5, 0]}\n", models[k][0]);
    write_file(scene, text);
    expect(run(ARGV(scene, "--method", "exact", "-o", h5), NULL), 2, models[k][1]);
    assert_false(exists(h5));
  }
  /* large but sane values run, and the summary holds no inf or nan.  The
   * stop at 0.1 lies below the round-off (1e-16 of 1e90) of every position,
   * so the motion is that of x_s = 0, a times the unit load's (linear
   * between impacts, Newton's law homogeneous): pressed from rest, the
   * mass sticks at once, is released, and hits twice in three periods
   * (test_stress_scale); it took 3 million impacts of round-off's size */
  char text[1024];
  snprintf(text, sizeof text, "%sforcing: {omega: 0.9, a: [1e90, 0]}\n"
           "run: {periods: 3, atol: 1e80}\n", CHAIN2);
  write_file(scene, text);
  int rc = run(ARGV(scene, "--method", "exact"), NULL);
  char *out = slurp(path("stdout"));
  assert_int_equal(rc, 0);
  assert_null(strstr(out, "inf"));
  assert_null(strstr(out, "nan"));
  const char *imp = strstr(out, "\n  impacts "), *stk = strstr(out, " sticks ");
  assert_non_null(imp);
  assert_non_null(stk);
  char *end = NULL;
  long nimp = strtol(imp + strlen("\n  impacts "), &end, 10);
  assert_true(end && *end == ' ');
  long nstk = strtol(stk + strlen(" sticks "), &end, 10);
  assert_true(end && (*end == ' ' || *end == '\n'));
  assert_int_equal(nimp, 2);
  assert_int_equal(nstk, 1);
  remove(scene);
}

/* ---- command line ---------------------------------------------------------- */
static void test_command_line(void **state)
{
  (void)state;
  expect(run(ARGV("ener"), NULL), 2, "did you mean 'vibroimpact energy'");
  expect(run(ARGV("runn"), NULL), 2, "did you mean 'vibroimpact run'");
  expect(run(ARGV("no-such-scene.yaml"), NULL), 2, "cannot open");
  expect(run(ARGV("--method", "rk4"), NULL), 2, "is not one of adams");
  expect(run(ARGV("--rtol", "10"), NULL), 2, "--rtol must lie in");
  expect(run(ARGV("--max-depth", "0"), NULL), 2, "--max-depth");
  expect(run(ARGV("--max-memory", "lots"), NULL), 2, "--max-memory");
  /* the output never replaces the scene it was computed from */
  char *scene = path("own.yaml"), *ln = path("own-link.h5");
  char text[512];
  snprintf(text, sizeof text, "%sforcing: {omega: 0.9, a: [0.5, 0]}\n", CHAIN2);
  write_file(scene, text);
  assert_int_equal(symlink("own.yaml", ln), 0);
  expect(run(ARGV(scene, "-o", scene), NULL), 2, "over the scene");
  expect(run(ARGV(scene, "-o", ln), NULL), 2, "over the scene");
  expect(run(ARGV(scene, "--impacts-csv", scene), NULL), 2, "over the scene");
  assert_string_equal(slurp(scene), text);
  unlink(ln);
  unlink(scene);
}

/* ---- every command through the same fault cases ------------------------- */
/* One command line: the command's own arguments around a scene and its
 * output options.  `out` says whether the command writes -o FILE. */
typedef struct cmd_case {
  const char *name;
  const char *args[12]; /* after the scene; NULL-terminated */
  int out;
} cmd_case;

static const cmd_case commands[] = {
    {"run", {"--periods", "3", NULL}, 1},
    {"energy", {NULL}, 1},
    {"sweep", {"--param", "forcing.omega", "--from", "0.8", "--to", "1.0",
               "--steps", "3", NULL}, 1},
    {"orbits", {NULL}, 0},
};

/* argv: app COMMAND SCENE ARGS... EXTRA... into a[] (static storage). */
static char *const *cmd_argv(const cmd_case *c, const char *scene,
                             const char *const *extra)
{
  static char *a[40];
  int k = 0;
  a[k++] = (char *)app;
  a[k++] = (char *)c->name;
  a[k++] = (char *)scene;
  for (int i = 0; c->args[i]; i++) a[k++] = (char *)c->args[i];
  for (int i = 0; extra && extra[i]; i++) a[k++] = (char *)extra[i];
  a[k] = NULL;
  return a;
}

static void test_every_command(void **state)
{
  (void)state;
  char scene[600];
  snprintf(scene, sizeof scene, "%s/fig2.yaml", VI_SCENE_DIR);
  char *copy = path("scene-copy.yaml");
  write_file(copy, slurp(scene));
  char *fifo = path("cmd-fifo"), *sub = path("cmd-dir");
  assert_int_equal(mkfifo(fifo, 0644), 0);
  assert_int_equal(mkdir(sub, 0755), 0);
  char *victim = path("cmd-victim"), *planted = path("cmd-planted.h5");
  char part[700];
  snprintf(part, sizeof part, "%s.part", planted);
  write_file(victim, "precious\n");
  assert_int_equal(symlink(victim, part), 0);
  char env[700];
  snprintf(env, sizeof env, "LD_PRELOAD=%s", hook);
  char *big = path("cmd-big.yaml");
  {
    FILE *bf = fopen(big, "w");
    assert_non_null(bf);
    fputs(slurp(scene), bf);
    for (int i = 0; i < 800; i++)
      fprintf(bf, "# %098d\n", i); /* 80 KB of comment */
    assert_int_equal(fclose(bf), 0);
  }
  for (size_t k = 0; k < sizeof commands / sizeof commands[0]; k++) {
    const cmd_case *c = &commands[k];
    print_message("command %s\n", c->name);
    /* the standard output lost: exit 1, said */
    if (access("/dev/full", W_OK) == 0) {
      const char *json[] = {"--json", NULL};
      expect(run(cmd_argv(c, scene, strcmp(c->name, "run") ? json : NULL),
                 "/dev/full"), 1, "cannot write the standard output");
    }
    if (!c->out) continue;
    /* outputs that are not ours to replace, refused before any work */
    const char *bad[3] = {"/dev/null", fifo, sub};
    for (int b = 0; b < 3; b++) {
      const char *o[] = {"-o", bad[b], "--quiet", NULL};
      expect(run(cmd_argv(c, scene, o), NULL), 1, "refusing");
      char p[700];
      snprintf(p, sizeof p, "%s.part", bad[b]);
      assert_false(exists(p));
    }
    struct stat st;
    assert_int_equal(lstat(fifo, &st), 0);
    assert_true(S_ISFIFO(st.st_mode));
    /* a link planted at OUT.part is not followed */
    const char *o1[] = {"-o", planted, "--quiet", NULL};
    expect(run(cmd_argv(c, scene, o1), NULL), 1, "symbolic link");
    assert_string_equal(slurp(victim), "precious\n");
    /* the scene itself, named as the output: a usage error */
    const char *o2[] = {"-o", copy, "--quiet", NULL};
    expect(run(cmd_argv(c, copy, o2), NULL), 2, "over the scene");
    assert_string_equal(slurp(copy), slurp(scene));
    /* a full disk: exit 1 (no crash), the old file kept, no partial file */
    char *out = path("cmd-full.h5");
    write_file(out, "old contents\n");
    const char *o3[] = {"-o", out, "--quiet", NULL};
    int rc = finish(start(cmd_argv(c, scene, o3), NULL, env, "VI_FAULT_BUDGET=2000"));
    expect(rc, 1, NULL);
    assert_string_equal(slurp(out), "old contents\n");
    snprintf(part, sizeof part, "%s.part", out);
    assert_false(exists(part));
    /* and, with room, a valid file, also of a scene over 64 KiB (an HDF5
     * attribute's limit) */
    rc = run(cmd_argv(c, big, o3), NULL);
    expect(rc, 0, NULL);
    hid_t f = H5Fopen(out, H5F_ACC_RDONLY, H5P_DEFAULT);
    assert_true(f >= 0);
    H5Fclose(f);
    remove(out);
  }
  unlink(fifo);
  rmdir(sub);
}

/* A file size limit (RLIMIT_FSIZE, SIGXFSZ ignored): every write past it
 * fails with EFBIG as on a full disk, HDF5's own writes included, with no
 * tmpfs and no root.  Each command's file grows past the limit mid-write:
 * exit 1 naming the file, no partial file, the old file kept. */
static void test_file_size_limit(void **state)
{
  (void)state;
  char scene[600];
  snprintf(scene, sizeof scene, "%s/fig2.yaml", VI_SCENE_DIR);
  char *out = path("fsize.h5"), part[700];
  snprintf(part, sizeof part, "%s.part", out);
  /* limits below each file's size (run 1.7 MB, energy 21 kB, sweep and
   * basins 30 kB, truncation 29 kB: built in memory, vi_h5_util.h) and
   * above what the start writes */
  const struct { long limit; const char *args[24]; } cases[] = {
      {524288, {"run", scene, "--periods", "1000", NULL}},
      {40000, {"energy", scene, NULL}},
      {16384, {"sweep", scene, "--param", "forcing.omega", "--from", "0.8",
               "--to", "1.0", "--steps", "3", NULL}},
      {16384, {"basins", scene, "--param", "initial.x[2]", "--from", "-1", "--to",
               "0.09", "--steps", "3", "--param2", "initial.v[2]", "--from2", "-1",
               "--to2", "1", "--steps2", "3", NULL}},
      {8000, {"truncation", scene, NULL}}, /* 29 kB */
  };
  for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
    char *argv[32];
    int k = 0;
    argv[k++] = (char *)app;
    for (int i = 0; cases[c].args[i]; i++) argv[k++] = (char *)cases[c].args[i];
    argv[k++] = (char *)"-o";
    argv[k++] = out;
    argv[k++] = (char *)"--quiet";
    argv[k] = NULL;
    write_file(out, "old contents\n");
    fsize_limit = cases[c].limit;
    int rc = finish(start(argv, NULL, NULL, NULL));
    fsize_limit = 0;
    print_message("%-7s over a %ld-byte file size limit: exit %d\n", cases[c].args[0],
                  cases[c].limit, rc);
    expect(rc, 1, "File too large");
    assert_non_null(strstr(slurp(path("stderr")), "fsize.h5.part"));
    assert_string_equal(slurp(out), "old contents\n");
    assert_false(exists(part));
    /* and with no limit the same command writes a valid file */
    expect(run(argv, NULL), 0, NULL);
    hid_t f = H5Fopen(out, H5F_ACC_RDONLY, H5P_DEFAULT);
    assert_true(f >= 0);
    H5Fclose(f);
  }
  remove(out);
}

/* One nesting limit for every reader of scenes: the loader (run), the
 * --set editor (run --set, a --set value), sweep and orbits refuse 100 000
 * levels with the same message at the same place, before loading the
 * document (which takes minutes at that depth: 10 s of CPU bound it). */
static void test_nesting(void **state)
{
  (void)state;
  char *deep = path("nest.yaml");
  FILE *f = fopen(deep, "w");
  assert_non_null(f);
  fputs("a: ", f);
  for (int k = 0; k < 100000; k++) fputc('[', f);
  for (int k = 0; k < 100000; k++) fputc(']', f);
  fputc('\n', f);
  assert_int_equal(fclose(f), 0);
  char scene[600], msg[200];
  snprintf(scene, sizeof scene, "%s/fig2.yaml", VI_SCENE_DIR);
  snprintf(msg, sizeof msg, "%s:1:35: nesting deeper than 32 levels (the limit; "
           "a scene needs 5)", deep);
  cpu_limit = 10;
  expect(run(ARGV(deep), NULL), 2, msg);
  expect(run(ARGV(deep, "--set", "forcing.omega=0.9"), NULL), 2, msg);
  expect(run(ARGV("sweep", deep, "--param", "forcing.omega", "--from", "0.8",
                  "--to", "1", "--steps", "2"), NULL), 2, msg);
  expect(run(ARGV("orbits", deep), NULL), 2, msg);
  expect(run(ARGV("orbits", deep, "--set", "forcing.omega=0.9"), NULL), 2, msg);
  /* --max-depth D holds on the --set path too, in every command: the
   * limit named is the one given */
  expect(run(ARGV(deep, "--set", "forcing.omega=0.9", "--max-depth", "40"), NULL), 2,
         "nesting deeper than 40 levels");
  expect(run(ARGV("sweep", deep, "--set", "forcing.omega=0.9", "--max-depth", "40",
                  "--param", "forcing.omega", "--from", "0.8", "--to", "1", "--steps",
                  "2"), NULL), 2, "nesting deeper than 40 levels");
  expect(run(ARGV("orbits", deep, "--set", "forcing.omega=0.9", "--max-depth", "40"),
             NULL), 2, "nesting deeper than 40 levels");
  /* and below a scene's own nesting (fig2's model: chain: {...}, 3
   * levels), fig2 itself is refused */
  expect(run(ARGV(scene, "--set", "forcing.omega=0.9", "--max-depth", "2"), NULL), 2,
         "nesting deeper than 2 levels");
  expect(run(ARGV("sweep", scene, "--set", "forcing.omega=0.9", "--max-depth", "2",
                  "--param", "forcing.a[1]", "--from", "0.1", "--to", "0.2",
                  "--steps", "2"), NULL), 2, "nesting deeper than 2 levels");
  expect(run(ARGV("orbits", scene, "--set", "forcing.omega=0.9", "--max-depth", "2"),
             NULL), 2, "nesting deeper than 2 levels");
  /* a --set value 60 000 levels deep (one argument holds 128 KiB) */
  size_t len = 2 * 60000 + 32;
  char *val = malloc(len);
  assert_non_null(val);
  int k = snprintf(val, len, "forcing.omega=");
  for (int i = 0; i < 60000; i++) val[k++] = '[';
  for (int i = 0; i < 60000; i++) val[k++] = ']';
  val[k] = '\0';
  expect(run(ARGV(scene, "--set", val), NULL), 2,
         "nesting deeper than 32 levels (the limit; a scene needs 5)");
  expect(run(ARGV("sweep", scene, "--set", val, "--param", "forcing.a[1]",
                  "--from", "0.1", "--to", "0.2", "--steps", "2"), NULL), 2,
         "nesting deeper than 32 levels (the limit; a scene needs 5)");
  cpu_limit = 0;
  free(val);
  remove(deep);
}

/* An integer root attribute of an HDF5 file (-1 if absent). */
static long long h5_attr(hid_t f, const char *name)
{
  long long v = -1;
  if (H5Aexists(f, name) <= 0) return -1;
  hid_t a = H5Aopen(f, name, H5P_DEFAULT);
  H5Aread(a, H5T_NATIVE_LLONG, &v);
  H5Aclose(a);
  return v;
}

/* The interrupted study's file: valid, complete = 0, points_done of
 * points_total matching the /sweep/done flags, no .part left. */
static void check_incomplete(const char *h5, long long total)
{
  char part[700];
  snprintf(part, sizeof part, "%s.part", h5);
  assert_false(exists(part));
  hid_t f = H5Fopen(h5, H5F_ACC_RDONLY, H5P_DEFAULT);
  assert_true(f >= 0);
  long long done = h5_attr(f, "points_done");
  assert_int_equal(h5_attr(f, "complete"), 0);
  assert_int_equal(h5_attr(f, "points_total"), total);
  assert_true(done >= 0 && done < total);
  int *flags = malloc(sizeof(int) * (size_t)total);
  assert_non_null(flags);
  hid_t d = H5Dopen2(f, "sweep/done", H5P_DEFAULT);
  assert_true(d >= 0);
  assert_true(H5Dread(d, H5T_NATIVE_INT, H5S_ALL, H5S_ALL, H5P_DEFAULT, flags) >= 0);
  long long sum = 0;
  for (long long i = 0; i < total; i++) sum += flags[i];
  assert_int_equal(sum, done);
  print_message("  interrupted file: complete = 0, %lld of %lld points\n", done, total);
  free(flags);
  H5Dclose(d);
  H5Fclose(f);
}

/* Interrupted studies: SIGINT and SIGTERM answered with 130 and 143, the
 * points done written to a valid file marked incomplete (and in JSON),
 * through .part; orbits answers with the program's common handler. */
static void test_interrupted_studies(void **state)
{
  (void)state;
  char scene[600];
  snprintf(scene, sizeof scene, "%s/fig2.yaml", VI_SCENE_DIR);
  char *h5 = path("intr.h5");
  const char *lng[] = {"--param", "forcing.omega", "--from", "0.8", "--to",
                       "1.0", "--steps", "20000", "--transient", "500", "--record",
                       "4", "--threads", "1", "--quiet", "-o", h5, NULL};
  cmd_case sweep_long = {"sweep", {NULL}, 1};
  expect(signal_in("sweep -o (20000 steps)", cmd_argv(&sweep_long, scene, lng), 0.2,
                   SIGINT), 130, "marked incomplete");
  check_incomplete(h5, 20000);
  remove(h5);
  expect(signal_in("sweep -o (20000 steps)", cmd_argv(&sweep_long, scene, lng), 0.2,
                   SIGTERM), 143, "interrupted (SIGTERM)");
  check_incomplete(h5, 20000);
  remove(h5);
  /* basins: a 150 x 150 grid of initial states */
  const char *bas[] = {"--param", "initial.x[2]", "--from", "-1", "--to", "0.09",
                       "--steps", "150", "--param2", "initial.v[2]", "--from2",
                       "-1", "--to2", "1", "--steps2", "150", "--transient", "500",
                       "--record", "4", "--threads", "1", "--quiet", "-o", h5, NULL};
  cmd_case basins = {"basins", {NULL}, 1};
  expect(signal_in("basins -o (150 x 150)", cmd_argv(&basins, scene, bas), 0.2,
                   SIGINT), 130, "marked incomplete");
  check_incomplete(h5, 150LL * 150);
  remove(h5);
  /* JSON: the points done, flagged */
  const char *js[] = {"--param", "forcing.omega", "--from", "0.8", "--to", "1.0",
                      "--steps", "20000", "--transient", "500", "--record", "4",
                      "--threads", "1", "--json", NULL};
  expect(signal_in("sweep --json", cmd_argv(&sweep_long, scene, js), 0.2, SIGINT),
         130, NULL);
  const char *out = slurp(path("stdout"));
  assert_non_null(strstr(out, "\"complete\": false"));
  assert_non_null(strstr(out, "\"points_done\": "));
  /* orbits: the common handler (a continuation of a million steps) */
  const char *orb[] = {"--continue", "forcing.omega", "--to", "1.5", "--steps",
                       "1000000", "--json", NULL};
  cmd_case orbits = {"orbits", {NULL}, 0};
  expect(signal_in("orbits", cmd_argv(&orbits, scene, orb), 0.2, SIGTERM), 143,
         "interrupted (SIGTERM): stopped, no file left behind");
  expect(signal_in("orbits", cmd_argv(&orbits, scene, orb), 0.2, SIGINT), 130,
         "interrupted (SIGINT): stopped, no file left behind");
}

/* An interrupted truncation study: the rows done, in a valid file marked
 * incomplete (the signal waits for two rows of the table, whatever the
 * machine's speed, looking every 10 ms; the FE beam's 18 later rows take
 * half a second in all, its 20-mode reference as long before them). */
static void test_interrupted_truncation(void **state)
{
  (void)state;
  char scene[600], part[700];
  snprintf(scene, sizeof scene, "%s/beam_fe.yaml", VI_SCENE_DIR);
  char *h5 = path("trunc.h5");
  snprintf(part, sizeof part, "%s.part", h5);
  pid_t pid = start(ARGV("truncation", scene, "--modes", "1..20", "--reference",
                         "20", "-o", h5),
                    NULL, NULL, NULL);
  int rows = 0;
  for (int i = 0; i < 60000 && rows < 2; i++) { /* at most 600 s */
    usleep(10000);
    FILE *f = fopen(path("stdout"), "r");
    char line[512];
    rows = 0;
    while (f && fgets(line, sizeof line, f)) {
      char *end; /* a row: its k, then the columns */
      long k = strtol(line, &end, 10);
      if (end != line && k >= 1 && *end == ' ') rows++;
    }
    if (f) fclose(f);
  }
  int st;
  assert_int_equal(waitpid(pid, &st, WNOHANG), 0); /* still in the rows */
  kill(pid, SIGINT);
  assert_int_equal(finish(pid), 130);
  assert_non_null(strstr(slurp(path("stderr")), "marked incomplete"));
  assert_false(exists(part));
  hid_t f = H5Fopen(h5, H5F_ACC_RDONLY, H5P_DEFAULT);
  assert_true(f >= 0);
  hid_t g = H5Gopen2(f, "truncation", H5P_DEFAULT);
  assert_true(g >= 0);
  assert_int_equal(h5_attr(g, "complete"), 0);
  hid_t d = H5Dopen2(g, "rows/k", H5P_DEFAULT), sp = H5Dget_space(d);
  hsize_t n = 0;
  H5Sget_simple_extent_dims(sp, &n, NULL);
  print_message("  interrupted truncation: complete = 0, %llu of 20 rows\n",
                (unsigned long long)n);
  assert_true(n >= 2 && n < 20);
  H5Sclose(sp);
  H5Dclose(d);
  H5Gclose(g);
  H5Fclose(f);
  remove(h5);
}

int main(int argc, char **argv)
{
  if (argc < 3) {
    fprintf(stderr, "usage: test_faults PATH-TO-vibroimpact PATH-TO-hook.so\n");
    return 2;
  }
  app = argv[1];
  hook = argv[2];
  /* a sanitized program accepts the preloaded hook before its runtime */
  char asan[1024];
  const char *prev = getenv("ASAN_OPTIONS");
  snprintf(asan, sizeof asan, "%s%sverify_asan_link_order=0", prev ? prev : "",
           prev && *prev ? ":" : "");
  setenv("ASAN_OPTIONS", asan, 1);
  if (!mkdtemp(dir)) return 2;
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_full_disk),
      cmocka_unit_test(test_non_regular_outputs),
      cmocka_unit_test(test_stdout_full),
      cmocka_unit_test(test_signals),
      cmocka_unit_test(test_limits),
      cmocka_unit_test(test_ranges),
      cmocka_unit_test(test_command_line),
      cmocka_unit_test(test_every_command),
      cmocka_unit_test(test_interrupted_studies),
      cmocka_unit_test(test_interrupted_truncation),
      cmocka_unit_test(test_file_size_limit),
      cmocka_unit_test(test_nesting),
  };
  int rc = cmocka_run_group_tests(tests, NULL, NULL);
  remove(path("stdout"));
  remove(path("stderr"));
  rmdir(dir);
  for (int k = 0; k < npaths; k++) free(paths[k]);
  return rc;
}
