#!/usr/bin/env bash
# Runs list_markers.py on a capture (same arguments), again when RenderDoc's replay itself dies
# of a segfault: RenderDoc 1.24 replaying on lavapipe now and then crashes inside the driver's
# queue thread before it has read anything (a known RenderDoc-on-llvmpipe fault, not the
# capture's). Any other failure, a missing pass or resource included, fails at once.
set -uo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
for attempt in 1 2 3; do
  /usr/bin/python3 "$here/list_markers.py" "$@"
  status=$?
  [ "$status" -eq 139 ] || exit "$status"
  echo "check_capture: RenderDoc's replay crashed (segfault, attempt $attempt of 3)" >&2
done
exit "$status"
