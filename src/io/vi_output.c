/* vi_output.c - the one output path of every command (vi_output.h).
 * Regular files only are replaced, always through TARGET.part renamed once
 * every write, flush, sync and close succeeded: a failed run never touches
 * TARGET.  A symlink is followed to its target (which is replaced, the link
 * stays); a character device is written directly by stream outputs and
 * never replaced; FIFOs, sockets, directories and the scene are refused.
 * The checks run before anything is computed. */
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "vibroimpact.h"
#include "vibroimpact/vi_output.h"

#ifndef PATH_MAX
#define PATH_MAX 4096
#endif

static int refuse(vi_diag *d, const char *path, int code, const char *fmt,
                  const char *a, const char *b)
{
  if (d) {
    memset(d, 0, sizeof *d);
    d->code = code;
    snprintf(d->file, sizeof d->file, "%.*s", (int)sizeof d->file - 1, path);
    snprintf(d->message, sizeof d->message, fmt, a, b);
  }
  return code;
}

static const char *file_kind(mode_t m)
{
  return S_ISDIR(m)    ? "a directory"
         : S_ISCHR(m)  ? "a character device"
         : S_ISBLK(m)  ? "a block device"
         : S_ISFIFO(m) ? "a FIFO"
         : S_ISSOCK(m) ? "a socket"
                       : "not a regular file";
}

/* The directory part of p ("." when none) into dir. */
static void dir_of(const char *p, char *dir, size_t len)
{
  const char *slash = strrchr(p, '/');
  if (!slash)
    snprintf(dir, len, ".");
  else if (slash == p)
    snprintf(dir, len, "/");
  else
    snprintf(dir, len, "%.*s", (int)(slash - p), p);
}

int vi_output_part(const char *target, char *part, int len)
{
  if (!target || !*target || !part || len < 1) return VI_ERR_ARG;
  int k = snprintf(part, (size_t)len, "%s.part", target);
  if (k < 0 || k >= len) {
    part[0] = '\0';
    return VI_ERR_LIMIT;
  }
  return VI_OK;
}

/* Same file by device and inode: of the files if both exist, else of the
 * folders plus the last names. */
int vi_output_same(const char *a, const char *b)
{
  if (!a || !b || !*a || !*b || !strcmp(a, "-") || !strcmp(b, "-")) return 0;
  struct stat sa, sb;
  int ea = stat(a, &sa) == 0, eb = stat(b, &sb) == 0;
  if (ea && eb) return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
  if (ea != eb) return 0;
  char da[PATH_MAX], db[PATH_MAX];
  dir_of(a, da, sizeof da);
  dir_of(b, db, sizeof db);
  const char *na = strrchr(a, '/'), *nb = strrchr(b, '/');
  na = na ? na + 1 : a;
  nb = nb ? nb + 1 : b;
  if (strcmp(na, nb) != 0 || stat(da, &sa) != 0 || stat(db, &sb) != 0) return 0;
  return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
}

int vi_output_resolve(const char *path, char *target, int len, vi_diag *d)
{
  return vi_output_check(path, VI_OUTPUT_REGULAR, NULL, target, len, NULL, d);
}

int vi_output_check(const char *path, int flags, const char *scene,
                    char *target, int len, int *kindp, vi_diag *d)
{
  if (d) memset(d, 0, sizeof *d);
  if (kindp) *kindp = VI_OUTPUT_FILE;
  if (!path || !*path || !target || len < 2 || (flags & ~VI_OUTPUT_STREAM))
    return refuse(d, path ? path : "", VI_ERR_ARG, "%.200s%.200s",
                  "no output file name", "");
  if ((flags & VI_OUTPUT_STREAM) && !strcmp(path, "-")) {
    memcpy(target, "-", 2);
    if (kindp) *kindp = VI_OUTPUT_STDOUT;
    return VI_OK;
  }
  char cur[PATH_MAX], dir[PATH_MAX];
  if (strlen(path) + 6 >= sizeof cur)
    return refuse(d, path, VI_ERR_LIMIT, "%.200s%.200s", "output path too long", "");
  snprintf(cur, sizeof cur, "%s", path);
  struct stat st;
  int exists = 0;
  for (int hop = 0;; hop++) {
    if (hop > 40)
      return refuse(d, path, VI_ERR_IO, "%.200s%.200s",
                    "too many levels of symbolic links", "");
    if (lstat(cur, &st) != 0) {
      if (errno != ENOENT)
        return refuse(d, path, VI_ERR_IO, "cannot write %.200s: %.200s", cur,
                      strerror(errno));
      break; /* a new file */
    }
    if (!S_ISLNK(st.st_mode)) {
      exists = 1;
      break;
    }
    /* follow the link: its text is relative to the link's directory */
    char link[PATH_MAX];
    ssize_t k = readlink(cur, link, sizeof link - 1);
    if (k < 0)
      return refuse(d, path, VI_ERR_IO, "cannot read the link %.200s: %.200s", cur,
                    strerror(errno));
    link[k] = '\0';
    if (link[0] == '/' || !strchr(cur, '/')) {
      if ((size_t)k + 6 >= sizeof cur)
        return refuse(d, path, VI_ERR_LIMIT, "%.200s%.200s", "output path too long",
                      "");
      memcpy(cur, link, (size_t)k + 1);
    } else {
      dir_of(cur, dir, sizeof dir);
      if (strlen(dir) + (size_t)k + 8 >= sizeof cur)
        return refuse(d, path, VI_ERR_LIMIT, "%.200s%.200s", "output path too long",
                      "");
      snprintf(cur, sizeof cur, "%.2000s/%.2000s", dir, link);
    }
  }
  if (exists && S_ISCHR(st.st_mode) && (flags & VI_OUTPUT_STREAM)) {
    /* written straight through, never replaced (/dev/null, a tty) */
    if (access(cur, W_OK) != 0)
      return refuse(d, path, VI_ERR_IO, "cannot write %.200s: %.200s", cur,
                    strerror(errno));
    if ((int)strlen(cur) >= len)
      return refuse(d, path, VI_ERR_LIMIT, "%.200s%.200s",
                    "output path longer than the buffer", "");
    memcpy(target, cur, strlen(cur) + 1);
    if (kindp) *kindp = VI_OUTPUT_DEVICE;
    return VI_OK;
  }
  if (exists && !S_ISREG(st.st_mode))
    return refuse(d, path, VI_ERR_IO,
                  "refusing to write %.200s: it is %.200s (output goes to regular "
                  "files only)",
                  cur, file_kind(st.st_mode));
  if (exists && access(cur, W_OK) != 0)
    return refuse(d, path, VI_ERR_IO, "cannot write %.200s: %.200s", cur,
                  strerror(errno));
  if (scene && vi_output_same(cur, scene))
    return refuse(d, path, VI_ERR_ARG,
                  "refusing to write the output over the scene %.200s%.200s",
                  scene, "");
  dir_of(cur, dir, sizeof dir);
  struct stat ds;
  if (stat(dir, &ds) != 0)
    return refuse(d, path, VI_ERR_IO, "cannot write %.200s: %.200s", cur,
                  strerror(errno));
  if (!S_ISDIR(ds.st_mode))
    return refuse(d, path, VI_ERR_IO, "cannot write %.200s: %.200s", cur,
                  "its folder is not a directory");
  if (access(dir, W_OK | X_OK) != 0)
    return refuse(d, path, VI_ERR_IO, "cannot write %.200s: %.200s", cur,
                  strerror(errno));
  /* TARGET.part is ours to replace, but only if it is a plain file (a link
   * planted there would send the output elsewhere) */
  char part[PATH_MAX + 8];
  vi_output_part(cur, part, (int)sizeof part);
  if (lstat(part, &st) == 0 && !S_ISREG(st.st_mode))
    return refuse(d, path, VI_ERR_IO,
                  "refusing to write %.200s: it exists and is %.200s", part,
                  S_ISLNK(st.st_mode) ? "a symbolic link" : file_kind(st.st_mode));
  /* the real test of the folder (access() says yes to root even where the
   * file system will not take a file): create PATH.part and remove it */
  remove(part);
  int fd = open(part, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (fd < 0)
    return refuse(d, path, VI_ERR_IO, "cannot write %.200s: %.200s", cur,
                  strerror(errno));
  close(fd);
  unlink(part);
  if ((int)strlen(cur) >= len)
    return refuse(d, path, VI_ERR_LIMIT, "%.200s%.200s",
                  "output path longer than the buffer", "");
  memcpy(target, cur, strlen(cur) + 1);
  return VI_OK;
}

static int fail_io(vi_diag *d, const char *name, const char *what, int e)
{
  return refuse(d, name, VI_ERR_IO, "cannot write %.200s: %.200s", name,
                e ? strerror(e) : what);
}

int vi_output_open(const char *target, int kind, FILE **out, vi_diag *d)
{
  if (d) memset(d, 0, sizeof *d);
  if (out) *out = NULL;
  if (!target || !*target || !out || kind < VI_OUTPUT_FILE ||
      kind > VI_OUTPUT_STDOUT)
    return refuse(d, target ? target : "", VI_ERR_ARG, "%.200s%.200s",
                  "no output to open", "");
  if (kind == VI_OUTPUT_STDOUT) {
    *out = stdout;
    return VI_OK;
  }
  if (kind == VI_OUTPUT_DEVICE) {
    /* the device itself, never created or truncated ("a" has no O_TRUNC) */
    if (!(*out = fopen(target, "a"))) return fail_io(d, target, "", errno);
    return VI_OK;
  }
  char part[PATH_MAX + 8];
  if (vi_output_part(target, part, (int)sizeof part))
    return refuse(d, target, VI_ERR_LIMIT, "%.200s%.200s", "output path too long", "");
  /* a stale PATH.part is ours, but only a plain file: never follow a link
   * planted between the check and now */
  struct stat st;
  if (lstat(part, &st) == 0) {
    if (!S_ISREG(st.st_mode))
      return refuse(d, target, VI_ERR_IO,
                    "refusing to write %.200s: it exists and is %.200s", part,
                    S_ISLNK(st.st_mode) ? "a symbolic link" : file_kind(st.st_mode));
    unlink(part);
  }
  int fd = open(part, O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
  if (fd < 0) return fail_io(d, part, "", errno);
  if (!(*out = fdopen(fd, "w"))) {
    int e = errno;
    close(fd);
    unlink(part);
    return fail_io(d, part, "", e);
  }
  return VI_OK;
}

int vi_output_commit(const char *target, vi_diag *d)
{
  if (d) memset(d, 0, sizeof *d);
  char part[PATH_MAX + 8];
  if (!target || vi_output_part(target, part, (int)sizeof part))
    return refuse(d, target ? target : "", VI_ERR_ARG, "%.200s%.200s",
                  "no output to commit", "");
  int fd = open(part, O_RDONLY | O_NOFOLLOW | O_CLOEXEC);
  int e = 0;
  if (fd < 0 || fsync(fd) != 0) e = errno ? errno : EIO;
  if (fd >= 0 && close(fd) != 0 && !e) e = errno;
  if (!e && rename(part, target) != 0) e = errno;
  if (e) {
    unlink(part);
    return fail_io(d, target, "", e);
  }
  return VI_OK;
}

int vi_output_close(FILE **f, const char *target, int kind, vi_diag *d)
{
  if (d) memset(d, 0, sizeof *d);
  if (!f || !*f || !target || kind < VI_OUTPUT_FILE || kind > VI_OUTPUT_STDOUT)
    return refuse(d, target ? target : "", VI_ERR_ARG, "%.200s%.200s",
                  "no output to close", "");
  FILE *s = *f;
  *f = NULL;
  errno = 0;
  int bad = ferror(s) != 0;
  int e = bad ? EIO : 0;
  if (fflush(s) != 0 && !e) e = errno ? errno : EIO;
  if (kind == VI_OUTPUT_FILE && !e && fsync(fileno(s)) != 0) e = errno;
  if (kind != VI_OUTPUT_STDOUT && fclose(s) != 0 && !e) e = errno ? errno : EIO;
  const char *name = kind == VI_OUTPUT_STDOUT ? "the standard output" : target;
  if (kind == VI_OUTPUT_FILE) {
    char part[PATH_MAX + 8];
    if (vi_output_part(target, part, (int)sizeof part)) return VI_ERR_ARG;
    if (!e && rename(part, target) != 0) e = errno;
    if (e) unlink(part);
  }
  return e ? fail_io(d, name, "", e) : VI_OK;
}

void vi_output_discard(FILE **f, const char *target, int kind)
{
  if (f && *f) {
    if (kind == VI_OUTPUT_STDOUT) fflush(*f);
    else fclose(*f);
    *f = NULL;
  }
  char part[PATH_MAX + 8];
  if (kind == VI_OUTPUT_FILE && target && !vi_output_part(target, part, (int)sizeof part))
    unlink(part);
}
