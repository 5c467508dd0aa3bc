/* vi_enospc.c - an LD_PRELOAD hook that makes the disk look full for files
 * named *.part once VI_FAULT_BUDGET bytes have been written to them (or
 * reserved with fallocate); with VI_FAULT_NO_FALLOCATE set, fallocate on
 * them fails as on a file system without preallocation.  The fault suite uses it where it cannot mount
 * a small tmpfs (not root, or no mount in the container). */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>
#include <unistd.h>

static long long used;

static int is_part(int fd)
{
  char link[64], path[4096];
  snprintf(link, sizeof link, "/proc/self/fd/%d", fd);
  ssize_t k = readlink(link, path, sizeof path - 1);
  if (k < 5) return 0;
  path[k] = '\0';
  return !strcmp(path + k - 5, ".part");
}

static long long budget(void)
{
  const char *b = getenv("VI_FAULT_BUDGET");
  return b ? strtoll(b, NULL, 10) : -1;
}

/* 1: this many more bytes go past the budget */
static int over(int fd, long long bytes)
{
  long long b = budget();
  if (b < 0 || !is_part(fd)) return 0;
  if (used + bytes > b) return 1;
  used += bytes;
  return 0;
}

#define NEXT(name, type) ((type)dlsym(RTLD_NEXT, name))

ssize_t write(int fd, const void *buf, size_t n)
{
  if (over(fd, (long long)n)) {
    errno = ENOSPC;
    return -1;
  }
  return NEXT("write", ssize_t (*)(int, const void *, size_t))(fd, buf, n);
}

ssize_t pwrite(int fd, const void *buf, size_t n, off_t off)
{
  if (over(fd, (long long)n)) {
    errno = ENOSPC;
    return -1;
  }
  return NEXT("pwrite", ssize_t (*)(int, const void *, size_t, off_t))(
      fd, buf, n, off);
}

ssize_t pwrite64(int fd, const void *buf, size_t n, off_t off)
{
  if (over(fd, (long long)n)) {
    errno = ENOSPC;
    return -1;
  }
  return NEXT("pwrite64", ssize_t (*)(int, const void *, size_t, off_t))(
      fd, buf, n, off);
}

int fallocate(int fd, int mode, off_t off, off_t len)
{
  long long b = budget();
  if (getenv("VI_FAULT_NO_FALLOCATE") && is_part(fd)) {
    errno = EOPNOTSUPP; /* a file system without preallocation */
    return -1;
  }
  if (b >= 0 && is_part(fd) && (long long)off + (long long)len > b) {
    errno = ENOSPC;
    return -1;
  }
  return NEXT("fallocate", int (*)(int, int, off_t, off_t))(fd, mode, off,
                                                            len);
}

int fallocate64(int fd, int mode, off_t off, off_t len)
{
  return fallocate(fd, mode, off, len);
}
