/* vi_status.c - status names and messages from the single VI_STATUS_LIST. */
#include <stdarg.h>
#include <stdio.h>

#include "vi_internal.h"

const char *vi_status_name(int code)
{
  switch (code) {
#define VI_NAME_(name, value, msg) case value: return #name;
    VI_STATUS_LIST(VI_NAME_)
#undef VI_NAME_
  }
  return "VI_UNKNOWN";
}

const char *vi_strerror(int code)
{
  switch (code) {
#define VI_MSG_(name, value, msg) case value: return msg;
    VI_STATUS_LIST(VI_MSG_)
#undef VI_MSG_
  }
  return "unknown status code";
}

int vi_fail(char *buf, int code, const char *fmt, ...)
{
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(buf, VI_MSG_LEN, fmt, ap);
  va_end(ap);
  return code;
}
