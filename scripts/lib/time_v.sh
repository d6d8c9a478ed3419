# Readers of /usr/bin/time -v logs, shared by the benchmarks (source
# scripts/lib/time_v.sh from the repository root).

# Exits 1 where /usr/bin/time (GNU time, for -v) is missing.
require_time_v() {
  [[ -x /usr/bin/time ]] || {
    echo "/usr/bin/time missing (apt-get install time)" >&2; exit 1; }
}

# Wall seconds and peak RSS (MB) from the log $1.
wall_s() {
  awk -F': ' '/Elapsed \(wall clock\)/ {n = split($2, t, ":"); s = 0;
    for (i = 1; i <= n; ++i) s = s * 60 + t[i]; printf "%.1f", s}' "$1"; }
# User + system CPU seconds from the log $1.
cpu_s() {
  awk -F': ' '/User time|System time/ {s += $2} END {printf "%.1f", s}' "$1"; }
peak_mb() { awk -F': ' '/Maximum resident set size/ {printf "%.0f", $2/1024}' "$1"; }

# The 1-minute load average now: what else the machine was doing.
load() { cut -d' ' -f1 /proc/loadavg; }
