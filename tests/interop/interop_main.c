/* sarloc-cyclone-interop: a Cyclone DDS (C API) peer of sarloc's Fast DDS nodes, built from the
 * same IDL files (idl/) by Cyclone's idlc. Proves that another vendor can read every sarloc
 * topic and feed the core daemon (docs/topics.md, "Interoperability with other DDS vendors").
 *
 *   sarloc-cyclone-interop subscribe --domain 150 --timeout 60   # next to a running mission
 *   sarloc-cyclone-interop publish --domain 151 --rescuer cyc-1   # next to a lone sarloc-core
 *
 * Discovery needs CYCLONEDDS_URI pointing at tests/interop/cyclonedds.xml (loopback). Exit
 * codes: 0 passed, 1 a check failed, 2 bad command line, 4 could not run. */
#define _GNU_SOURCE
#include <getopt.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "interop_modes.h"

volatile sig_atomic_t interop_stop_requested = 0;

static void request_stop(int signal_number) {
  (void)signal_number;
  interop_stop_requested = 1;
}

static void usage(FILE* out) {
  fprintf(out,
          "usage: sarloc-cyclone-interop subscribe|publish [options]\n"
          "  --domain N            DDS domain id (required)\n"
          "  --timeout S           subscribe: stop after S seconds; publish: wait S seconds for the\n"
          "                        daemon to be discovered (default 60)\n"
          "  --min-samples N       subscribe: valid samples every topic must deliver (default 1)\n"
          "  --rescuer ID          publish: rescuer id to publish as (default cyclone-r1)\n"
          "  --epochs N            publish: measurement epochs to walk (default 16)\n"
          "  --answer-timeout S    publish: wait for the daemon's answer to one epoch (default 3)\n"
          "subscribe runs until SIGINT/SIGTERM or the timeout, then prints a table per topic.\n");
}

/* A number in [lo, hi], the whole argument consumed. */
static int parse_number(const char* text, double lo, double hi, double* out) {
  char* end = NULL;
  const double v = strtod(text, &end);
  if (end == text || *end != '\0' || !(v >= lo && v <= hi)) return 0;
  *out = v;
  return 1;
}

int main(int argc, char** argv) {
  InteropOptions options = {.domain = 0,
                            .timeout_s = 60.0,
                            .min_samples = 1,
                            .rescuer_id = "cyclone-r1",
                            .epochs = 16,
                            .answer_timeout_s = 3.0};
  if (argc < 2 || strcmp(argv[1], "--help") == 0) {
    usage(argc < 2 ? stderr : stdout);
    return argc < 2 ? kExitUsage : kExitOk;
  }
  const char* mode = argv[1];
  static const struct option longopts[] = {{"domain", required_argument, NULL, 'd'},
                                           {"timeout", required_argument, NULL, 't'},
                                           {"min-samples", required_argument, NULL, 'm'},
                                           {"rescuer", required_argument, NULL, 'r'},
                                           {"epochs", required_argument, NULL, 'e'},
                                           {"answer-timeout", required_argument, NULL, 'a'},
                                           {NULL, 0, NULL, 0}};
  int have_domain = 0;
  int opt;
  int index = 0;
  double v = 0.0;
  optind = 2;
  while ((opt = getopt_long(argc, argv, "", longopts, &index)) != -1) {
    int ok = 1;
    switch (opt) {
      case 'd':
        ok = parse_number(optarg, 0, 232, &v);
        options.domain = (uint32_t)v;
        have_domain = ok;
        break;
      case 't':
        ok = parse_number(optarg, 1, 3600, &options.timeout_s);
        break;
      case 'm':
        ok = parse_number(optarg, 0, 1e9, &v);
        options.min_samples = (int)v;
        break;
      case 'r':
        options.rescuer_id = optarg;
        ok = strlen(optarg) >= 1 && strlen(optarg) <= 64;
        break;
      case 'e':
        ok = parse_number(optarg, 1, 1000, &v);
        options.epochs = (int)v;
        break;
      case 'a':
        ok = parse_number(optarg, 0.1, 60, &options.answer_timeout_s);
        break;
      default:
        usage(stderr);
        return kExitUsage;
    }
    if (!ok) {
      fprintf(stderr, "--%s = '%s': out of range or not a number (see --help)\n", longopts[index].name, optarg);
      return kExitUsage;
    }
  }
  if (!have_domain) {
    fprintf(stderr, "--domain is required\n");
    return kExitUsage;
  }

  struct sigaction action;
  memset(&action, 0, sizeof action);
  action.sa_handler = request_stop;
  sigaction(SIGINT, &action, NULL);
  sigaction(SIGTERM, &action, NULL);

  if (strcmp(mode, "subscribe") == 0) return run_subscribe(&options);
  if (strcmp(mode, "publish") == 0) return run_publish(&options);
  fprintf(stderr, "unknown mode '%s': subscribe or publish\n", mode);
  return kExitUsage;
}
