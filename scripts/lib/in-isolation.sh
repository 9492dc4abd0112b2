# Sourced by scripts that start DDS processes: in_isolation CMD... runs CMD in
# ../shared/tools/isolated (a namespace with only loopback; inside one already, it just runs
# CMD), and refuses, exit 70, where there is no such tool: never on the shared network.
in_isolation() {
  local isolated
  isolated="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)/../shared/tools/isolated"
  if [[ ! -x "$isolated" ]]; then
    echo "$(basename "$0"): $isolated not found: refusing to run DDS processes on the shared network" >&2
    exit 70
  fi
  "$isolated" "$@"
}
