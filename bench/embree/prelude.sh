# What bench/embree's scripts share, sourced from the repository's root: Embree 3 installed
# (Debian's libembree-dev, as root) or a clear error, embree-bench built under the build
# lock, and the header every results file starts with.
# Sets: lock (PRISM_LOCK names the lock that serialises builds and benchmarks on a shared
# machine), bin (the embree-bench binary), out (bench/results).

lock=${PRISM_LOCK:-/tmp/prism-cargo.lock}

if [[ ! -e /usr/include/embree3/rtcore.h ]]; then
    if [[ $(id -u) == 0 ]]; then
        apt-get update && apt-get install -y libembree-dev
    else
        echo "$(basename "$0"): Embree 3 is missing; install it with: apt-get install libembree-dev" >&2
        exit 1
    fi
fi

(cd bench/embree && flock "$lock" cargo build --release --quiet)
bin=${CARGO_TARGET_DIR:-bench/embree/target}/release/embree-bench
out=bench/results
mkdir -p "$out"

# The results header: what ran, where, on which versions. $1 is the title.
results_header() {
    echo "# $1 ($(date -u '+%Y-%m-%d %H:%M UTC'), prism $(git rev-parse --short HEAD))"
    echo "machine: $(lscpu | sed -n 's/^Model name: *//p'), $(nproc) logical CPUs, shared with other work; load average $(cut -d' ' -f1-3 /proc/loadavg)"
    echo "Embree $(dpkg-query -W -f '${Version}' libembree3-3 2>/dev/null || echo '?'), $(rustc --version)"
    echo "CPU: avx2 $(grep -qw avx2 /proc/cpuinfo && echo yes || echo no), avx512f $(grep -qw avx512f /proc/cpuinfo && echo yes || echo no)"
    echo
}
