# scripts/slurm-timelapse on a real, single-node Slurm brought up here in a
# temporary folder (munged, slurmctld, slurmd from Debian, as the current
# user, on loopback ports), every daemon shut down afterwards.  The frames
# the array rendered are checked against the same times rendered by hand.
# Skips, saying why, where Slurm cannot run: its programs are missing, or
# the user is not root (slurmd starts jobs as their owner).
. "$TOP/tests/tools/lib.sh"
plan 2
REAL="${DATA:-$TOP/../shared/data}/weather/meteoblue-basic-clouds-solar-1h.json"
WI="$BIN/wxinterp"
CR="$BIN/cloudrender"
export WXINTERP="$WI" CLOUDRENDER="$CR" NOISEBAKE="$BIN/noisebake"
C1=slurm_timelapse_array_renders_every_frame_and_the_dependent_job_encodes
C2=slurm_daemons_are_all_shut_down_afterwards

why=""
for p in munged slurmctld slurmd sbatch sinfo scontrol; do
	command -v $p >/dev/null 2>&1 || PATH=$PATH:/usr/sbin
	command -v $p >/dev/null 2>&1 || { why="$p is not installed (Debian's munge, slurmctld, slurmd, slurm-client; make deps)"; break; }
done
[ -z "$why" ] && [ "$(id -u)" -ne 0 ] && why="not root: slurmd runs jobs as their owners, which needs root"
[ -z "$why" ] && [ ! -f "$REAL" ] && why="no $REAL (shared data absent)"
command -v ffprobe >/dev/null 2>&1 || why="ffmpeg is not installed (Debian's ffmpeg; make deps)"
if [ -n "$why" ]; then
	skip $C1 "$why"
	skip $C2 "$why"
	exit 0
fi

S="$T/slurm"
mkdir -p "$S/state" "$S/spool" "$S/munge"
chmod 700 "$S/munge"
pids=""
# every daemon ended, then the folder removed, whatever happens
shutdown() {
	for p in $pids; do kill "$p" 2>/dev/null; done
	for p in $pids; do
		n=0
		while kill -0 "$p" 2>/dev/null && [ $n -lt 50 ]; do sleep 0.1; n=$((n + 1)); done
		kill -KILL "$p" 2>/dev/null
	done
}
trap 'shutdown; chmod -R u+w "$T" 2>/dev/null; rm -rf "$T"' EXIT
trap 'exit 1' INT TERM HUP

# two free loopback ports, as the kernel hands them out
ports=$(python3 -c 'import socket
s = [socket.socket() for _ in range(2)]
for x in s: x.bind(("127.0.0.1", 0))
print(" ".join(str(x.getsockname()[1]) for x in s))')
set -- $ports
ctld_port=$1 d_port=$2
host=$(hostname -s)
dd if=/dev/urandom of="$S/munge/munge.key" bs=1024 count=1 2>/dev/null
chmod 400 "$S/munge/munge.key"
cat >"$S/slurm.conf" <<EOF
ClusterName=cstest
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$d_port
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$S/munge/munge.sock
CredType=cred/munge
StateSaveLocation=$S/state
SlurmdSpoolDir=$S/spool
SlurmctldPidFile=$S/slurmctld.pid
SlurmdPidFile=$S/slurmd.pid
SlurmctldLogFile=$S/slurmctld.log
SlurmdLogFile=$S/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SwitchType=switch/none
MpiDefault=none
SchedulerType=sched/builtin
SchedulerParameters=sched_interval=1
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
JobCompType=jobcomp/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
NodeName=$host NodeAddr=127.0.0.1 CPUs=$(nproc) State=UNKNOWN
PartitionName=cstest Nodes=ALL Default=YES MaxTime=INFINITE State=UP
EOF
export SLURM_CONF="$S/slurm.conf"
munged -F -f --key-file="$S/munge/munge.key" --socket="$S/munge/munge.sock" \
	--log-file="$S/munge/munged.log" --pid-file="$S/munge/munged.pid" \
	--seed-file="$S/munge/munged.seed" >"$S/munged.out" 2>&1 &
pids="$!"
n=0
while [ ! -S "$S/munge/munge.sock" ] && [ $n -lt 50 ]; do sleep 0.1; n=$((n + 1)); done
slurmctld -D -f "$S/slurm.conf" >"$S/slurmctld.out" 2>&1 &
pids="$pids $!"
slurmd -D -f "$S/slurm.conf" >"$S/slurmd.out" 2>&1 &
pids="$pids $!"
n=0
while ! sinfo -h -o %t 2>/dev/null | grep -q idle && [ $n -lt 300 ]; do sleep 0.1; n=$((n + 1)); done

begin $C1
if ! sinfo -h -o %t 2>/dev/null | grep -q idle; then
	bad "the node did not come up: $(tail -n 3 "$S/slurmctld.log" "$S/slurmd.log" "$S/munged.out" 2>&1 | tr '\n' ' ' | head -c 600)"
else
	# 5 frames in chunks of 2: 3 tasks, then the video
	run "$TOP/scripts/slurm-timelapse" "$REAL" 2024-10-13T14:00Z 2024-10-13T15:20Z --step 20m \
		--size 32x18 --fps 5 --noise-size 16 --chunk 2 --wait -o "$T/farm" -- --quality low
	expect_rc 0
	[ "$(wc -l <"$T/out")" -eq 3 ] || bad "expected 3 job ids (noise, frames, video): $(cat "$T/out")"
	expect_err "5 frames in 3 tasks of 2"
	expect_only_files "$T/farm/frames" 5
	# the camera held for the whole video: FROM's default view
	look=$("$WI" --at 2024-10-13T14:00Z "$REAL" | "$CR" -v --wx - --noise "$T/farm/noise.exr" \
		--size 32x18 --quality low -o "$T/probe.png" 2>&1 |
		sed -n 's/.*looking azimuth \([0-9.]*\) deg, elevation \([-0-9.]*\) deg.*/\1,\2/p')
	i=0
	for t in 14:00 14:20 14:40 15:00 15:20; do
		f=$(printf '%s/farm/frames/%05d.png' "$T" $i)
		"$WI" --at "2024-10-13T${t}Z" "$REAL" | "$CR" -q --wx - --noise "$T/farm/noise.exr" \
			--size 32x18 --quality low --look "$look" -o "$T/hand.png" ||
			bad "the hand render of $t failed"
		same_pixels "$f" "$T/hand.png" || bad "frame $i is not 2024-10-13T${t}Z as rendered by hand"
		i=$((i + 1))
	done
	# one log a task: the array ran as 3 tasks
	nlog=$(ls "$T/farm/slurm/log" | grep -c '^frames-.*_[0-2]\.out$')
	[ "$nlog" -eq 3 ] || bad "$nlog array task logs, expected 3: $(ls "$T/farm/slurm/log" | tr '\n' ' ')"
	v=$(ffprobe -v error -select_streams v:0 -count_frames -show_entries \
		stream=codec_name,pix_fmt,nb_read_frames -of csv=p=0 "$T/farm/timelapse.mp4" 2>&1)
	[ "$v" = "h264,yuv420p,5" ] || bad "video: '$v', expected h264,yuv420p,5"
fi
end

begin $C2
shutdown
for p in $pids; do
	kill -0 "$p" 2>/dev/null && bad "daemon $p is still running"
done
pids=""
# no job step of ours either
ps -eo args 2>/dev/null | grep -F "$S" | grep -v grep >/dev/null && bad "a process still names $S"
end
