# Sourced by the integration scripts: starts dhr-server on an ephemeral loopback port and stops it (SIGINT,
# then removes the temporary directory) when the script exits.
# start_server SERVER_EXE SCENE TMPDIR [EXTRA SERVER ARGUMENTS...]  ->  sets server_pid, port and key_file (a new
# deployment key in TMPDIR: clients pass --key-file "$key_file"); fails the script if it never listens.
server_pid=""
port=""
stop_server() {
  [ -n "$server_pid" ] && kill -INT "$server_pid" 2>/dev/null && wait "$server_pid" 2>/dev/null
  [ -n "${server_tmp:-}" ] && rm -rf "$server_tmp"
  return 0
}
trap stop_server EXIT

start_server() {
  local exe="$1" scene="$2"
  server_tmp="$3"
  shift 3
  key_file="$server_tmp/dhr.key"
  "$exe" --gen-key "$key_file" 2>/dev/null || { echo "FAIL: dhr-server --gen-key"; exit 1; }
  "$exe" --scene "$scene" --port 0 --threads 1 --key-file "$key_file" "$@" 2>"$server_tmp/server.log" >/dev/null &
  server_pid=$!
  for _ in $(seq 1 300); do
    port="$(sed -n 's/.*listening on .*:\([0-9][0-9]*\)$/\1/p' "$server_tmp/server.log" | head -n1)"
    [ -n "$port" ] && return 0
    sleep 0.1
  done
  cat "$server_tmp/server.log"
  echo "FAIL: dhr-server did not listen"
  exit 1
}
