#!/usr/bin/env bash
# Cyclone DDS <-> sarloc (Fast DDS) interoperability, in two parts (docs/topics.md,
# "Interoperability with other DDS vendors"):
#   1. subscribe: a Cyclone reader of every sarloc topic next to a small mission
#      (tests/integration/mission/small.yaml); every value is checked, every topic must deliver;
#   2. publish: a Cyclone rescuer feeds a lone sarloc-core daemon and must get every epoch's
#      VictimEstimate and Guidance back.
#
#   cyclone_interop_test.sh BIN_DIR INTEROP_EXE SUBSCRIBE_DOMAIN PUBLISH_DOMAIN
#
# Registered with ctest (label interop). DDS traffic stays on loopback: outside a namespace of
# ../shared/tools/isolated it re-runs itself in one, or refuses. Every process it starts is
# stopped by pid on exit. Logs: the run directory printed at the start.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)
if [[ $# -ne 4 ]]; then
  echo "usage: $0 BIN_DIR INTEROP_EXE SUBSCRIBE_DOMAIN PUBLISH_DOMAIN" >&2
  exit 2
fi
if [[ "${SARLOC_ISOLATED:-}" != 1 ]]; then
  isolated="$root/../shared/tools/isolated"
  [[ -x "$isolated" ]] && exec "$isolated" "$0" "$@"
  echo "$0: not inside a loopback-only namespace and no $isolated: refusing to run DDS" >&2
  exit 70
fi
bin=$1 interop=$2 sub_domain=$3 pub_domain=$4
mission_file="$root/tests/integration/mission/small.yaml"
mission_limit_s=50   # about 11 s here; its own time limit (300 mission s at speedup 8) ends it first
export CYCLONEDDS_URI="file://$here/cyclonedds.xml"

run_dir=$(mktemp -d /tmp/sarloc-interop.XXXXXX)
echo "logs: $run_dir"
started=()  # process group ids (each started with setsid, so its children go with it)

stop() {  # stop PID's group: SIGTERM, then SIGKILL after 5 s
  local pid=$1
  kill -0 "$pid" 2>/dev/null || return 0
  kill -TERM -- "-$pid" 2>/dev/null || true
  for _ in $(seq 50); do
    kill -0 "$pid" 2>/dev/null || return 0
    sleep 0.1
  done
  kill -KILL -- "-$pid" 2>/dev/null || true
}
cleanup() {
  for pid in "${started[@]}"; do stop "$pid"; done
}
trap cleanup EXIT
reaped() {  # PID has been waited for: its id may be reused, never signal it again
  local keep=() pid
  for pid in "${started[@]}"; do [[ "$pid" == "$1" ]] || keep+=("$pid"); done
  started=("${keep[@]}")
}

# Waits for PID up to SECONDS; sets `rc` (124 on timeout, the process left running).
wait_for() {
  local pid=$1 limit=$2 t0=$SECONDS
  while kill -0 "$pid" 2>/dev/null && ((SECONDS - t0 < limit)); do sleep 0.2; done
  if kill -0 "$pid" 2>/dev/null; then
    rc=124
  else
    rc=0
    wait "$pid" || rc=$?
    reaped "$pid"
  fi
}

show() {  # a log, indented
  echo "--- $1"
  sed 's/^/    /' "$1" | tail -n "${2:-60}"
}

failed=0
t_start=$SECONDS

# --- 1. subscribe: every topic of a running mission -------------------------------------
setsid "$interop" subscribe --domain "$sub_domain" --timeout $((mission_limit_s + 10)) \
  >"$run_dir/subscribe.out" 2>&1 &
sub_pid=$!
started+=("$sub_pid")
setsid "$bin/sarloc-mission" "$mission_file" --domain "$sub_domain" --run-dir "$run_dir/mission" \
  --log-level warn >"$run_dir/mission.out" 2>&1 &
mission_pid=$!
started+=("$mission_pid")

wait_for "$mission_pid" "$mission_limit_s"
mission_rc=$rc
if ((mission_rc == 124)); then
  echo "FAIL: the mission did not finish within $mission_limit_s s"
  stop "$mission_pid"
  wait "$mission_pid" 2>/dev/null || true
  reaped "$mission_pid"
  failed=1
elif ((mission_rc != 0)); then
  echo "FAIL: sarloc-mission exited with $mission_rc (1 = a victim not found)"
  failed=1
fi
# TRANSIENT_LOCAL samples sent just before the mission ended are in flight: a moment for them.
sleep 0.5
kill -TERM "$sub_pid" 2>/dev/null || true
wait_for "$sub_pid" 10
sub_rc=$rc
echo "subscribe: exit $sub_rc after $((SECONDS - t_start)) s (mission exit $mission_rc)"
show "$run_dir/subscribe.out"
if ((sub_rc != 0)); then
  failed=1
  show "$run_dir/mission.out" 30
fi

# --- 2. publish: a Cyclone rescuer and a lone core daemon ----------------------------------
t_pub=$SECONDS
setsid "$bin/sarloc-core" -c "$mission_file" --domain "$pub_domain" --log-level info \
  >"$run_dir/core.log" 2>&1 &
core_pid=$!
started+=("$core_pid")
pub_rc=0
# As r1, a rescuer of the mission: the daemon serves only its mission's roster (core.admission).
"$interop" publish --domain "$pub_domain" --rescuer r1 --timeout 15 >"$run_dir/publish.out" 2>&1 || pub_rc=$?
stop "$core_pid"
wait "$core_pid" 2>/dev/null || true
reaped "$core_pid"
echo "publish: exit $pub_rc after $((SECONDS - t_pub)) s"
show "$run_dir/publish.out"
if ((pub_rc != 0)); then
  failed=1
  show "$run_dir/core.log" 30
fi

echo "total: $((SECONDS - t_start)) s"
if ((failed)); then
  echo "cyclone interop: FAILED (logs in $run_dir)"
  exit 1
fi
rm -rf "$run_dir"
echo "cyclone interop: passed"
