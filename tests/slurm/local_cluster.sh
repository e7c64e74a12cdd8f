# A one-node Slurm cluster on this machine, for the farm test (sourced by farm_test.sh). Everything lives in
# one directory: a fresh munge key and socket, slurm.conf, state, spool and logs; the daemons (munged,
# slurmctld, slurmd as node "localhost") are this script's own processes, on ports 16817/16818 so that a
# system Slurm is left alone. Clients find the cluster through SLURM_CONF. No system service is touched.
#   cluster_start DIR   starts it and waits until the node is idle; returns 1 (with the logs on stderr) if it
#                       cannot start
#   cluster_stop        cancels every job, waits for them to end (20 s at most), stops the daemons (SIGTERM,
#                       SIGKILL after 10 s), removes DIR (idempotent)

cluster_log_tail() {
  local f
  for f in "$CLUSTER_DIR"/log/*; do [ -s "$f" ] && { echo "--- $f"; tail -n 15 "$f"; }; done >&2
}

cluster_start() {
  [ -n "${1:-}" ] && [ -d "$1" ] || { echo "cluster_start: '${1:-}' is not a directory" >&2; return 1; }
  CLUSTER_DIR=$1
  mkdir -p "$CLUSTER_DIR"/{key,run,state,spool,log}
  # munged checks that its socket's directories are searchable by all and its key is private.
  chmod 755 "$CLUSTER_DIR" "$CLUSTER_DIR/run"
  chmod 700 "$CLUSTER_DIR/key"
  dd if=/dev/urandom of="$CLUSTER_DIR/key/munge.key" bs=1024 count=1 status=none
  chmod 400 "$CLUSTER_DIR/key/munge.key"
  local socket=$CLUSTER_DIR/run/munge.sock
  if ! munged --key-file="$CLUSTER_DIR/key/munge.key" --socket="$socket" --pid-file="$CLUSTER_DIR/run/munged.pid" \
      --log-file="$CLUSTER_DIR/log/munged.log" --seed-file="$CLUSTER_DIR/key/munged.seed"; then
    echo "munged did not start" >&2; cluster_log_tail; return 1
  fi
  cat > "$CLUSTER_DIR/slurm.conf" <<EOF
ClusterName=candela-farm-test
SlurmctldHost=localhost
SlurmctldPort=16817
SlurmdPort=16818
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$socket
StateSaveLocation=$CLUSTER_DIR/state
SlurmdSpoolDir=$CLUSTER_DIR/spool
SlurmctldPidFile=$CLUSTER_DIR/run/slurmctld.pid
SlurmdPidFile=$CLUSTER_DIR/run/slurmd.pid
SlurmctldLogFile=$CLUSTER_DIR/log/slurmctld.log
SlurmdLogFile=$CLUSTER_DIR/log/slurmd.log
ProctrackType=proctrack/pgid
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MpiDefault=none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
KillWait=5
NodeName=localhost NodeHostname=$(hostname) NodeAddr=127.0.0.1 CPUs=$(nproc) RealMemory=1000 State=UNKNOWN
PartitionName=farm Nodes=localhost Default=YES MaxTime=INFINITE State=UP
EOF
  export SLURM_CONF=$CLUSTER_DIR/slurm.conf
  if ! slurmctld -c -f "$SLURM_CONF" || ! slurmd -f "$SLURM_CONF" -N localhost; then
    echo "slurmctld or slurmd did not start" >&2; cluster_log_tail; return 1
  fi
  local i
  for i in $(seq 60); do
    [ "$(sinfo -h -N -o %T 2>/dev/null)" = idle ] && return 0
    sleep 0.5
  done
  echo "the node did not become idle in 30 s: $(sinfo -N 2>&1)" >&2; cluster_log_tail; return 1
}

cluster_stop() {
  [ -n "${CLUSTER_DIR:-}" ] || return 0
  local pidfile pid i
  if [ -n "${SLURM_CONF:-}" ] && [ -f "$CLUSTER_DIR/run/slurmctld.pid" ]; then
    scancel --user=root 2>/dev/null || true
    for i in $(seq 40); do [ -z "$(squeue -h 2>/dev/null)" ] && break; sleep 0.5; done
  fi
  for pidfile in slurmd slurmctld munged; do
    pid=$(cat "$CLUSTER_DIR/run/$pidfile.pid" 2>/dev/null) || continue
    kill "$pid" 2>/dev/null || continue
    for i in $(seq 40); do kill -0 "$pid" 2>/dev/null || break; sleep 0.25; done
    kill -KILL "$pid" 2>/dev/null || true  # still there after 10 s
  done
  rm -rf "$CLUSTER_DIR"
  CLUSTER_DIR=
}
