# bench/work-precision-large/wpl-machine.sh: sourced by run.sh and run-melt.sh.
# wpl_machine LOGS ROOT LMP "mode ..." writes LOGS/machine.txt (start time,
# CPU, load, commit, binary, the run's settings) on a first run, or appends
# a "resumed" line; parse.py / parse-melt.py print it with the results.
wpl_machine() {
  local logs=$1 root=$2 lmp=$3 mode=$4
  if [ ! -s "$logs/machine.txt" ]; then
    {
      echo "start $(date -u '+%Y-%m-%d %H:%M UTC')"
      echo "nproc $(nproc)"
      echo "cpu $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//')"
      echo "load_start $(cut -d' ' -f1-3 /proc/loadavg)"
      echo "commit $(git -C "$root" rev-parse --short HEAD 2>/dev/null)"
      echo "binary $lmp"
      echo "$mode"
    } > "$logs/machine.txt"
  else
    echo "resumed $(date -u '+%Y-%m-%d %H:%M UTC') load $(cut -d' ' -f1-3 /proc/loadavg)" >> "$logs/machine.txt"
  fi
}
