#!/usr/bin/env bash
# Throwaway one-node Slurm cluster on this machine, for scale-out tests.
#
#   slurm_cluster.sh start DIR          start munged, slurmctld, slurmd configured under DIR;
#                                       prints `export SLURM_CONF=...` (also in DIR/env.sh)
#   slurm_cluster.sh stop DIR           stop exactly the daemons started for DIR (idempotent)
#   slurm_cluster.sh run DIR -- CMD...  start, run CMD with SLURM_CONF set, stop whatever happens;
#                                       exits with CMD's status
#   slurm_cluster.sh status DIR         exit 0 if all three daemons of DIR are alive
#
# Exit codes: 0 ok, 77 skip (this machine cannot run the daemons: not root, binaries missing,
# no free port, cannot bind), 1 real failure (the daemon logs' tails are printed to stderr).
# SLURM_CLUSTER_STRICT=1 turns a skip into a failure (for CI jobs that must run it).
# Timeouts (seconds): SLURM_CLUSTER_START_TIMEOUT (60), SLURM_CLUSTER_STOP_TIMEOUT (20).
# Ports: SLURM_CLUSTER_CTLD_PORT / SLURM_CLUSTER_SLURMD_PORT, else two free ones are picked.
# See docs/scaleout_harness.md.
# shellcheck disable=SC2046,SC2206,SC2207  # pid lists are split on purpose
set -uo pipefail

SELF=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)/$(basename "${BASH_SOURCE[0]}")
START_TIMEOUT=${SLURM_CLUSTER_START_TIMEOUT:-60}
STOP_TIMEOUT=${SLURM_CLUSTER_STOP_TIMEOUT:-20}
SKIP=77

log() { echo "slurm_cluster: $*" >&2; }
die() { log "error: $*"; exit 1; }
skip() {
  if [ "${SLURM_CLUSTER_STRICT:-0}" = 1 ]; then log "error: cannot run (strict mode): $*"; exit 1; fi
  echo "slurm_cluster: SKIP: $*" >&2
  exit "$SKIP"
}
usage() { sed -n '2,16s/^# \{0,1\}//p' "$SELF" >&2; exit "${1:-2}"; }

# ---------------------------------------------------------------- processes
# alive PID: the process exists and is not a zombie.
alive() {
  local s
  read -r s 2>/dev/null < "/proc/$1/stat" || return 1
  s=${s##*) }
  [ "${s%% *}" != Z ]
}
# start_time PID: field 22 of /proc/PID/stat (guards against PID reuse).
start_time() {
  local s
  read -r s 2>/dev/null < "/proc/$1/stat" || return 1
  s=${s##*) }
  set -- $s
  echo "${20}"
}
cmdline() { tr '\0' ' ' < "/proc/$1/cmdline" 2>/dev/null; }
# pid_of NAME: the pid from DIR/run/NAME.pid if that process is alive and was started for DIR
# (its command line names a path under DIR); nothing otherwise.
pid_of() {
  local f="$DIR/run/$1.pid" p
  [ -r "$f" ] || return 1
  read -r p 2>/dev/null < "$f" || return 1
  [[ "$p" =~ ^[0-9]+$ ]] || return 1
  alive "$p" || return 1
  case "$(cmdline "$p")" in *"$1"*"$DIR/"*) echo "$p" ;; *) return 1 ;; esac
}
# descendants PID...: all live descendants of the given pids (not the pids themselves).
descendants() {
  local roots=("$@")
  local -A kids=()
  local f s pid ppid
  for f in /proc/[0-9]*/stat; do
    read -r s 2>/dev/null < "$f" || continue
    pid=${s%% *}; s=${s##*) }; set -- $s; ppid=$2
    kids[$ppid]+=" $pid"
  done
  local queue=("${roots[@]}") out=() p c
  while [ ${#queue[@]} -gt 0 ]; do
    p=${queue[0]}; queue=("${queue[@]:1}")
    for c in ${kids[$p]:-}; do out+=("$c"); queue+=("$c"); done
  done
  echo "${out[@]:-}"
}
# step_daemons: slurmstepd processes of this cluster (their log fd or cwd is under DIR).
step_daemons() {
  local p f
  for p in $(pgrep -x slurmstepd 2>/dev/null); do
    for f in "/proc/$p/cwd" /proc/"$p"/fd/*; do
      case "$(readlink "$f" 2>/dev/null)" in "$DIR/"*) echo "$p"; break ;; esac
    done
  done
}
# wait_gone SECONDS PID...: wait until none of the pids is alive; returns 1 on timeout.
wait_gone() {
  local secs=$1; shift
  local end=$((SECONDS + secs)) p any
  while :; do
    any=0
    for p in "$@"; do alive "$p" && any=1; done
    [ $any = 0 ] && return 0
    [ $SECONDS -ge $end ] && return 1
    sleep 0.2
  done
}
# terminate SECONDS PID...: SIGTERM, bounded wait, SIGKILL, bounded wait.
terminate() {
  local secs=$1; shift
  [ $# -gt 0 ] || return 0
  kill -TERM "$@" 2>/dev/null
  wait_gone "$secs" "$@" && return 0
  log "still alive after ${secs}s, sending SIGKILL: $*"
  kill -KILL "$@" 2>/dev/null
  wait_gone 5 "$@"
}

# ---------------------------------------------------------------- helpers
set_dir() { # DIR create | DIR exists EXIT_CODE_IF_MISSING
  [ -n "${1:-}" ] || usage
  if [ "${2:-}" = create ]; then mkdir -p "$1" || die "cannot create $1"
  elif [ ! -d "$1" ]; then log "no such directory: $1 (nothing running)"; exit "$3"; fi
  DIR=$(cd "$1" && pwd -P) || die "cannot enter $1"
  CONF=$DIR/slurm.conf
  HOST=$(hostname -s 2>/dev/null || hostname)
}
listening_ports() {
  local f
  for f in /proc/net/tcp /proc/net/tcp6; do
    [ -r "$f" ] || continue
    while read -r _ addr _ st _; do
      [ "$st" = 0A ] && echo $((16#${addr##*:}))
    done < <(tail -n +2 "$f")
  done
}
# free_port EXCLUDE: a port in 12000-31999 (below the usual ephemeral range) that nothing listens on.
free_port() {
  local used p
  used=" $(listening_ports | tr '\n' ' ') $1 "
  for _ in $(seq 1 200); do
    p=$((12000 + RANDOM % 20000))
    case "$used" in *" $p "*) continue ;; esac
    echo "$p"; return 0
  done
  return 1
}
tail_logs() {
  local f
  for f in "$DIR"/log/munged.log "$DIR"/log/slurmctld.log "$DIR"/log/slurmd.log "$DIR"/log/*.stdout; do
    [ -s "$f" ] || continue
    echo "----- last 25 lines of $f" >&2
    tail -n 25 "$f" >&2
  done
}
bind_failure() {
  grep -hiE 'address already in use|unable to bind|cannot bind|bind\(\).*(denied|not permitted)' \
    "$DIR"/log/*.log "$DIR"/log/*.stdout 2>/dev/null | head -n 1
}
preflight() {
  [ "$(id -u)" = 0 ] || skip "needs root (slurmd runs job steps as their user; SlurmUser=root)"
  local c missing=()
  for c in slurmctld slurmd slurmstepd munged munge unmunge sinfo squeue sbatch scancel scontrol timeout pgrep awk; do
    command -v "$c" >/dev/null 2>&1 || missing+=("$c")
  done
  [ ${#missing[@]} = 0 ] || skip "missing ${missing[*]} (apt-get install slurm-wlm munge: tests/setup_debian.sh)"
  [ -n "$HOST" ] || skip "no hostname"
}

# ---------------------------------------------------------------- start
write_conf() {
  local ctld_port=$1 slurmd_port=$2 cpus mem
  cpus=$(nproc 2>/dev/null || echo 1)
  mem=$(free -m 2>/dev/null | awk '/^Mem:/ { print $2 }')
  [[ "$mem" =~ ^[0-9]+$ ]] || mem=1000
  : > "$DIR/plugstack.conf"
  cat > "$CONF" <<EOF
# Generated by tests/scaleout/slurm_cluster.sh: a one-node test cluster on $HOST.
ClusterName=scaleout
SlurmctldHost=$HOST(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$DIR/munge/munge.socket.2
CredType=cred/munge
StateSaveLocation=$DIR/state
SlurmdSpoolDir=$DIR/spool
SlurmctldPidFile=$DIR/run/slurmctld.pid
SlurmdPidFile=$DIR/run/slurmd.pid
SlurmctldLogFile=$DIR/log/slurmctld.log
SlurmdLogFile=$DIR/log/slurmd.log
SlurmctldDebug=info
SlurmdDebug=info
PlugStackConfig=$DIR/plugstack.conf
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SchedulerType=sched/backfill
MpiDefault=none
ReturnToService=2
SlurmdParameters=config_overrides
MailProg=/bin/true
SlurmdTimeout=30
InactiveLimit=0
MinJobAge=300
NodeName=$HOST NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=$mem State=UNKNOWN
PartitionName=debug Nodes=$HOST Default=YES MaxTime=INFINITE State=UP
EOF
  cat > "$DIR/env.sh" <<EOF
export SLURM_CONF=$CONF
EOF
}

start_failed() { # REASON: classify, print logs, clean up what was started, exit
  local why=$1 b
  b=$(bind_failure)
  log "start failed: $why"
  tail_logs
  ( do_stop ) >/dev/null 2>&1
  [ -n "$b" ] && skip "cannot bind a port: $b"
  exit 1
}

do_start() {
  preflight
  local n
  for n in munged slurmctld slurmd; do
    pid_of "$n" >/dev/null && die "a cluster is already running in $DIR ($n pid $(pid_of "$n")); stop it first"
  done
  mkdir -p "$DIR"/{munge,run,log,state,spool} || die "cannot create directories under $DIR"
  chmod 700 "$DIR/munge"
  rm -f "$DIR"/run/*.pid

  # munge: own key, socket, pid, log and seed under DIR; --force because DIR may sit in a
  # directory that is not world-executable (munged wants that for its socket directory).
  local key=$DIR/munge/munge.key sock=$DIR/munge/munge.socket.2
  if [ ! -s "$key" ]; then
    if command -v mungekey >/dev/null 2>&1; then
      mungekey --create --keyfile="$key" 2>/dev/null || die "mungekey failed"
    else
      dd if=/dev/urandom of="$key" bs=1024 count=1 status=none || die "cannot write $key"
    fi
  fi
  chmod 600 "$key"

  local ctld_port=${SLURM_CLUSTER_CTLD_PORT:-} slurmd_port=${SLURM_CLUSTER_SLURMD_PORT:-}
  [ -n "$ctld_port" ] || ctld_port=$(free_port 0) || skip "no free TCP port for slurmctld"
  [ -n "$slurmd_port" ] || slurmd_port=$(free_port "$ctld_port") || skip "no free TCP port for slurmd"
  local used p
  used=" $(listening_ports | tr '\n' ' ') "
  for p in "$ctld_port" "$slurmd_port"; do
    [[ "$p" =~ ^[0-9]+$ ]] || die "bad port '$p'"
    case "$used" in *" $p "*) skip "TCP port $p is already in use" ;; esac
  done
  [ "$ctld_port" != "$slurmd_port" ] || die "slurmctld and slurmd ports must differ ($p)"
  write_conf "$ctld_port" "$slurmd_port"
  export SLURM_CONF=$CONF

  # Daemons get stdin/stdout/stderr away from the caller's pipes, so `start | ...` ends.
  timeout 20 munged --force --socket="$sock" --key-file="$key" --pid-file="$DIR/run/munged.pid" \
    --log-file="$DIR/log/munged.log" --seed-file="$DIR/munge/munged.seed" \
    </dev/null >>"$DIR/log/munged.stdout" 2>&1 || start_failed "munged exited with $?"
  local end=$((SECONDS + 15))
  until timeout 5 munge -n --socket="$sock" 2>/dev/null | timeout 5 unmunge --socket="$sock" >/dev/null 2>&1; do
    [ $SECONDS -ge $end ] && start_failed "munge credentials do not round-trip through $sock"
    sleep 0.2
  done

  timeout 30 slurmctld -f "$CONF" </dev/null >>"$DIR/log/slurmctld.stdout" 2>&1 \
    || start_failed "slurmctld exited with $?"
  timeout 30 slurmd -f "$CONF" </dev/null >>"$DIR/log/slurmd.stdout" 2>&1 \
    || start_failed "slurmd exited with $?"

  # Wait (bounded) for the node to register and become idle.
  end=$((SECONDS + START_TIMEOUT))
  local state="" grace=$((SECONDS + 5))
  while :; do
    state=$(timeout 5 sinfo -h -N -n "$HOST" -o %T 2>/dev/null | head -n 1)
    [ "$state" = idle ] && break
    if [ $SECONDS -ge $grace ]; then   # pid files are written shortly after the fork
      for n in munged slurmctld slurmd; do
        pid_of "$n" >/dev/null || start_failed "$n is not running (node state '${state:-unknown}')"
      done
    fi
    if [ $SECONDS -ge $end ]; then
      start_failed "node $HOST not idle after ${START_TIMEOUT}s (state '${state:-no answer}')$(timeout 5 scontrol show node "$HOST" 2>/dev/null | grep -o ' Reason=.*')"
    fi
    sleep 0.5
  done
  log "cluster up in $DIR (node $HOST idle, slurmctld port $ctld_port, slurmd port $slurmd_port)"
  echo "export SLURM_CONF=$CONF"
}

# ---------------------------------------------------------------- stop
do_stop() {
  local ctld slurmd munged steps tree=() rc=0
  ctld=$(pid_of slurmctld); slurmd=$(pid_of slurmd); munged=$(pid_of munged)
  steps=$(step_daemons)
  if [ -z "$ctld$slurmd$munged$steps" ]; then
    log "nothing running for $DIR"
    rm -f "$DIR"/run/{munged,slurmctld,slurmd}.pid 2>/dev/null
    return 0
  fi
  # Cancel this cluster's jobs while controller and munge are still up (bounded).
  if [ -n "$ctld" ] && [ -n "$munged" ] && [ -r "$CONF" ]; then
    local jobs end
    jobs=$(SLURM_CONF=$CONF timeout 5 squeue -h -o %A 2>/dev/null | sort -u | tr '\n' ' ')
    if [ -n "${jobs// /}" ]; then
      log "cancelling jobs: $jobs"
      SLURM_CONF=$CONF timeout 10 scancel $jobs 2>/dev/null
      end=$((SECONDS + 10))
      while [ -n "$(step_daemons)" ] && [ $SECONDS -lt $end ]; do sleep 0.2; done
    fi
  fi
  # Step daemons and their job processes, then slurmd/slurmctld (with slurmscriptd), then munged.
  steps=$(step_daemons)
  if [ -n "$steps" ]; then
    tree=($steps $(descendants $steps))
    log "killing leftover job steps: ${tree[*]}"
    terminate 5 "${tree[@]}" || rc=1
  fi
  tree=()
  [ -n "$slurmd" ] && tree+=("$slurmd")
  [ -n "$ctld" ] && tree+=("$ctld" $(descendants "$ctld"))
  if [ ${#tree[@]} -gt 0 ]; then terminate "$STOP_TIMEOUT" "${tree[@]}" || rc=1; fi
  if [ -n "$munged" ]; then terminate "$STOP_TIMEOUT" "$munged" || rc=1; fi
  rm -f "$DIR"/run/{munged,slurmctld,slurmd}.pid 2>/dev/null
  if [ $rc = 0 ]; then log "stopped cluster in $DIR"; else log "error: some processes of $DIR survived SIGKILL"; fi
  return $rc
}

# ---------------------------------------------------------------- run
do_watchdog() { # PARENT_PID PARENT_START: stop the cluster once the `run` process is gone
  local parent=$1 st=$2
  while [ "$(start_time "$parent" 2>/dev/null)" = "$st" ] && alive "$parent"; do sleep 1; done
  [ -e "$DIR/run/watchdog.done" ] && exit 0
  log "run process $parent is gone; stopping its command and the cluster"
  local cpid cst
  if read -r cpid cst 2>/dev/null < "$DIR/run/cmd.pid" && [ "$(start_time "$cpid")" = "$cst" ]; then
    terminate 5 "$cpid" $(descendants "$cpid")
  fi
  rm -f "$DIR/run/cmd.pid"
  do_stop
}

do_run() {
  [ "${1:-}" = -- ] && shift
  [ $# -gt 0 ] || usage
  local rc
  bash "$SELF" start "$DIR" >&2
  rc=$?
  [ $rc = 0 ] || exit $rc
  # Children of a signalled or SIGKILLed `run` must not outlive it: a detached watchdog
  # (one `sleep 1` per second) stops the cluster if this process disappears without cleanup.
  rm -f "$DIR/run/watchdog.done"
  setsid bash "$SELF" _watchdog "$DIR" $$ "$(start_time $$)" </dev/null >>"$DIR/log/watchdog.log" 2>&1 &
  WATCHDOG=$!
  CMD_PID=""
  CLEANED=0
  cleanup() {
    [ $CLEANED = 1 ] && return
    CLEANED=1
    trap '' INT TERM HUP   # a second signal (timeout signals child and group) must not cut this short
    if [ -n "$CMD_PID" ] && alive "$CMD_PID"; then
      log "stopping command (pid $CMD_PID)"
      terminate 5 "$CMD_PID" $(descendants "$CMD_PID")
    fi
    rm -f "$DIR/run/cmd.pid"
    do_stop
    touch "$DIR/run/watchdog.done"
    kill "$WATCHDOG" 2>/dev/null
  }
  trap cleanup EXIT
  trap 'exit 129' HUP
  trap 'exit 130' INT
  trap 'exit 143' TERM
  # The command sees only this cluster's configuration.
  unset $(compgen -e | grep '^SLURM_') 2>/dev/null
  export SLURM_CONF=$CONF
  "$@" <&0 &          # background + wait: signals reach the traps at once
  CMD_PID=$!
  echo "$CMD_PID $(start_time "$CMD_PID")" > "$DIR/run/cmd.pid"
  wait "$CMD_PID"
  rc=$?
  CMD_PID=""
  rm -f "$DIR/run/cmd.pid"
  exit $rc
}

# ---------------------------------------------------------------- main
cmd=${1:-}; shift || true
case "$cmd" in
  start) set_dir "${1:-}" create; do_start ;;
  stop) set_dir "${1:-}" exists 0; do_stop ;;
  run) set_dir "${1:-}" create; shift; do_run "$@" ;;
  status)
    set_dir "${1:-}" exists 1
    for n in munged slurmctld slurmd; do
      p=$(pid_of "$n") || { echo "$n: not running"; exit 1; }
      echo "$n: $p"
    done ;;
  _watchdog) set_dir "$1" exists 0; do_watchdog "$2" "$3" ;;
  -h|--help|help) usage 0 ;;
  *) usage ;;
esac
