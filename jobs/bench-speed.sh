#!/usr/bin/env bash
# The figures of issue 11 (speed), one benchmark after the other; run on an idle machine after
# jobs/build.sh (and, for the portable flock figure, a build-v3: -DBIOTA_NATIVE=OFF
# -DCMAKE_CXX_FLAGS=-march=x86-64-v3). Log with the load at each start: /tmp/final-bench.log.
set -uo pipefail
cd "$(dirname "$0")/.." || exit 1
source jobs/mpi-env.sh
log=/tmp/final-bench.log
stamp() { echo "=== $(date -u +%H:%M:%S) load: $(cut -d' ' -f1-3 /proc/loadavg) :: $*" | tee -a $log; }
# Every benchmark waits for the load to fall (the log shows the load at each start).
source jobs/wait-idle.sh
run() {
  wait_idle | tee -a $log
  stamp "$*"
  "$@" 2>&1 | tee -a $log
}
run mpirun -np 1 ./build/biota bench lbm
run mpirun -np 2 ./build/biota bench lbm
run ./build/biota bench flock --boids 100000 --steps 10
run ./build/biota bench flock --boids 1000000 --steps 5
# The same case started by mpirun, bound to a core as a user's run is: started alone, OpenMPI's
# singleton is unbound and often ran this short case slower (docs/performance.md, session 29).
run mpirun -np 1 ./build/biota bench flock --boids 1000000 --steps 5
run mpirun -np 2 ./build/biota bench flock --boids 1000000 --steps 5 --rounds 3
run mpiexec -n 2 build/biota_bench_wind --size 100 --steps 3 --compare
if [ -x build-v3/biota ]; then run build-v3/biota bench flock --boids 100000 --steps 10; fi
run jobs/seaweed-experiment.sh
for c in 1 3 5; do stamp "timers c$c"; tail -30 out/seaweed_c$c.log | tee -a $log; done
# The seaweed's cost per sphere in 1x, 3x and 10x larger tanks (grows the cases once, ~10 minutes).
run jobs/seaweed-weak-scaling.sh
stamp "done"
