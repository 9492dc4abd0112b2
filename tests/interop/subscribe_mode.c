#define _POSIX_C_SOURCE 200809L
#include <dds/dds.h>
#include <stdio.h>

#include "interop_modes.h"
#include "sarloc_topics.h"

typedef struct TopicTally {
  dds_entity_t reader;
  long valid;    /* samples that passed every check */
  long invalid;  /* samples with at least one failed check */
  long disposed; /* dispose / unregister notifications (no data) */
} TopicTally;

enum { kTakeBatch = 64 };

static void take_and_check(const SarlocTopic* topic, TopicTally* tally) {
  void* samples[kTakeBatch] = {NULL};
  dds_sample_info_t infos[kTakeBatch];
  int n;
  do {
    n = dds_take(tally->reader, samples, infos, kTakeBatch, kTakeBatch);
    if (n < 0) {
      fprintf(stderr, "%s: dds_take failed: %s\n", topic->name, dds_strretcode(n));
      return;
    }
    for (int i = 0; i < n; ++i) {
      if (!infos[i].valid_data) {
        tally->disposed++;
        continue;
      }
      CheckReport report = check_begin(topic->name);
      topic->check(samples[i], &report);
      if (report.failures == 0) {
        tally->valid++;
      } else {
        tally->invalid++;
      }
    }
    if (n > 0) dds_return_loan(tally->reader, samples, n);
  } while (n == kTakeBatch);
}

/* Prints the table and returns whether every topic passed. */
static int report(const TopicTally* tallies, int min_samples) {
  int failed = 0;
  printf("%-28s %8s %8s %8s %8s  %s\n", "topic", "valid", "invalid", "disposed", "writers", "verdict");
  for (int i = 0; i < kSarlocTopicCount; ++i) {
    const SarlocTopic* topic = &kSarlocTopics[i];
    const TopicTally* t = &tallies[i];
    dds_subscription_matched_status_t matched = {0};
    dds_requested_incompatible_qos_status_t incompatible = {0};
    dds_get_subscription_matched_status(t->reader, &matched);
    dds_get_requested_incompatible_qos_status(t->reader, &incompatible);
    char verdict[64] = "ok";
    if (t->invalid > 0) {
      snprintf(verdict, sizeof verdict, "FAIL: invalid values (see above)");
    } else if (incompatible.total_count > 0) {
      snprintf(verdict, sizeof verdict, "FAIL: a writer offered incompatible QoS");
    } else if (t->valid < min_samples) {
      snprintf(verdict, sizeof verdict, "FAIL: fewer than %d valid sample(s)", min_samples);
    }
    if (verdict[0] == 'F') failed = 1;
    printf("%-28s %8ld %8ld %8ld %8u  %s\n", topic->name, t->valid, t->invalid, t->disposed, matched.total_count,
           verdict);
    if (incompatible.total_count > 0) {
      printf("  %u incompatible writer(s); last policy: %s (id %u)\n", incompatible.total_count,
             sarloc_policy_name(incompatible.last_policy_id), incompatible.last_policy_id);
    }
  }
  return failed;
}

int run_subscribe(const InteropOptions* options) {
  const dds_entity_t participant = dds_create_participant(options->domain, NULL, NULL);
  if (participant < 0) {
    fprintf(stderr, "cannot create a participant on domain %u: %s\n", options->domain, dds_strretcode(participant));
    return kExitCannotRun;
  }
  const dds_entity_t waitset = dds_create_waitset(participant);
  TopicTally tallies[kSarlocTopicCount] = {{0}};
  for (int i = 0; i < kSarlocTopicCount; ++i) {
    const SarlocTopic* topic = &kSarlocTopics[i];
    const dds_entity_t t = dds_create_topic(participant, topic->descriptor, topic->name, NULL, NULL);
    dds_qos_t* qos = sarloc_endpoint_qos(topic);
    tallies[i].reader = t < 0 ? t : dds_create_reader(participant, t, qos, NULL);
    dds_delete_qos(qos);
    if (tallies[i].reader < 0) {
      fprintf(stderr, "%s: cannot create the reader: %s\n", topic->name, dds_strretcode(tallies[i].reader));
      dds_delete(participant);
      return kExitCannotRun;
    }
    const dds_entity_t condition = dds_create_readcondition(tallies[i].reader, DDS_ANY_STATE);
    dds_waitset_attach(waitset, condition, i);
  }
  printf("subscribed to %d sarloc topics on domain %u\n", kSarlocTopicCount, options->domain);
  fflush(stdout);

  const dds_time_t end = dds_time() + (dds_duration_t)(options->timeout_s * 1e9);
  while (!interop_stop_requested && dds_time() < end) {
    dds_waitset_wait(waitset, NULL, 0, DDS_MSECS(200));
    for (int i = 0; i < kSarlocTopicCount; ++i) take_and_check(&kSarlocTopics[i], &tallies[i]);
  }
  if (!interop_stop_requested) printf("timed out after %.0f s\n", options->timeout_s);
  const int failed = report(tallies, options->min_samples);
  dds_delete(participant);
  return failed ? kExitFailed : kExitOk;
}
