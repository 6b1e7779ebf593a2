# Sourced by .ci/run and the CI scripts (issue 43, CI under 40 minutes): the wall time and the
# processor time of each step. Processor time is user + system time of every process the shell
# has waited for (bash's `times`); a loaded machine stretches the wall time but hardly the
# processor time, so the two together say whether a slow run did more work or got fewer cores.
#   timing_start; COMMAND...; timing_report "what took"   ->  "what took 95 s (processor 181 s)"

# Sets timing_cpu_now: user + system seconds of the shell's finished children so far. Not to be
# called inside $(...): a subshell's counters start at zero.
timing_children_cpu() {
  local file
  file=$(mktemp)
  times >"$file"  # a builtin with a redirection runs in this shell
  timing_cpu_now=$(awk 'NR == 2 { total = 0
      for (i = 1; i <= 2; i++) { v = $i; sub(/s$/, "", v); split(v, p, "m"); total += p[1] * 60 + p[2] }
      printf "%d\n", total + 0.5 }' "$file")
  rm -f "$file"
}
timing_start() {
  timing_wall0=$SECONDS
  timing_children_cpu
  timing_cpu0=$timing_cpu_now
}
# Sets timing_wall and timing_cpu (seconds since timing_start) and prints LABEL with both.
timing_report() {
  timing_wall=$((SECONDS - timing_wall0))
  timing_children_cpu
  timing_cpu=$((timing_cpu_now - timing_cpu0))
  echo "$1 $timing_wall s (processor $timing_cpu s)"
}
