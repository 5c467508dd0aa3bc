/* vi_output.c - where an output file may go.  Output is written only to
 * regular files: a symlink is followed to its target (which is replaced,
 * the link stays), devices, FIFOs, sockets and directories are refused, and
 * the checks run before anything is computed.  The file itself is written
 * as TARGET.part and renamed, so a failed run never touches TARGET. */
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "vibroimpact.h"
#include "vibroimpact/vi_writer.h"

#ifndef PATH_MAX
#define PATH_MAX 4096
#endif

static int refuse(vi_diag *d, const char *path, int code, const char *fmt,
                  const char *a, const char *b)
{
  if (d) {
    memset(d, 0, sizeof *d);
    d->code = code;
    snprintf(d->file, sizeof d->file, "%s", path);
    snprintf(d->message, sizeof d->message, fmt, a, b);
  }
  return code;
}

static const char *kind(mode_t m)
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

int vi_output_resolve(const char *path, char *target, int len, vi_diag *d)
{
  if (d) memset(d, 0, sizeof *d);
  if (!path || !*path || !target || len < 2)
    return refuse(d, path ? path : "", VI_ERR_ARG, "%.200s%.200s",
                  "no output file name", "");
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
  if (exists && !S_ISREG(st.st_mode))
    return refuse(d, path, VI_ERR_IO,
                  "refusing to write %.200s: it is %.200s (output goes to regular "
                  "files only)",
                  cur, kind(st.st_mode));
  if (exists && access(cur, W_OK) != 0)
    return refuse(d, path, VI_ERR_IO, "cannot write %.200s: %.200s", cur,
                  strerror(errno));
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
  snprintf(part, sizeof part, "%.4090s.part", cur);
  if (lstat(part, &st) == 0 && !S_ISREG(st.st_mode))
    return refuse(d, path, VI_ERR_IO,
                  "refusing to write %.200s: it exists and is %.200s", part,
                  S_ISLNK(st.st_mode) ? "a symbolic link" : kind(st.st_mode));
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
