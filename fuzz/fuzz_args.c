/* fuzz_args.c - libFuzzer target: the command line.  The input is split at
 * NUL bytes into argv (at most 24 arguments) and parsed by vi_app_parse,
 * which touches no files; the commands themselves are stubs. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "../apps/vi_app.h"

/* the parser's table names them; nothing is run here */
int vi_cmd_run(const app_opts *o) { (void)o; return 0; }
int vi_cmd_energy(const app_opts *o) { (void)o; return 0; }
int vi_cmd_truncation(const app_opts *o) { (void)o; return 0; }
int vi_cmd_identify_main(int argc, char **argv) { (void)argc; (void)argv; return 0; }
int vi_cmd_curves_main(int argc, char **argv) { (void)argc; (void)argv; return 0; }

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
  char *buf = malloc(size + 1);
  if (!buf) return 0;
  memcpy(buf, data, size);
  buf[size] = '\0';
  char *argv[26];
  int argc = 0;
  argv[argc++] = "vibroimpact";
  for (size_t i = 0; i <= size && argc < 25;) {
    argv[argc++] = buf + i;
    i += strlen(buf + i) + 1;
  }
  argv[argc] = NULL;
  app_opts o;
  const app_cmd *cmd = NULL;
  int rc = vi_app_parse(argc, argv, &o, &cmd);
  if (rc < 0 && !cmd) abort(); /* "go on" must name a command */
  free(buf);
  return 0;
}
