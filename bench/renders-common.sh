# Shared by bench/render-vs.sh and bench/shadow-renders.sh (sourced, not run): the CPU
# time of one render and the median of a list. `cpu` writes its scratch file in $work,
# which the sourcing script sets.

# CPU seconds (user + system) of one command.
cpu() {
    /usr/bin/time -f "%U %S" -o "$work/time" "$@" >/dev/null 2>&1
    awk '{ print $1 + $2 }' "$work/time"
}

# The median of the arguments (the upper one of an even count's middle pair).
median() { printf '%s\n' "$@" | sort -g | awk '{ v[NR] = $1 } END { print v[int((NR + 1) / 2)] }'; }
