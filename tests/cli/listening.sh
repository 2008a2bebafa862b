# Sourced by the CLI tests that start a server (a site, a fake service) and need its port.
# listening_port FILE [PID]: waits up to a minute for the line "listening on PORT" in FILE and
# prints PORT; prints nothing when it never came, or at once when process PID ended first.
listening_port() {
  local file=$1 pid=${2:-} port=
  for _ in $(seq 1 600); do
    port=$(sed -n 's/^listening on //p' "$file" 2>/dev/null || true)
    [ -n "$port" ] && break
    [ -n "$pid" ] && ! kill -0 "$pid" 2>/dev/null && break
    sleep 0.1
  done
  echo "$port"
}
