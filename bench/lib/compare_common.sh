# Shared by the comparison scripts (bench/run_backend_compare.sh,
# bench/run_deposition_compare.sh); source it after setting `repo`.
#
# bench_parse_args "$@" sets `runs` (--runs K, default 1) and the array `positional`;
# every other option goes to the caller's bench_extra_option NAME VALUE, which returns
# (via the global `bench_consumed`) how many words it took (0: unknown option).
# bench_usage prints the calling script's header lines $bench_usage_lines and exits 2.

bench_usage() {
  sed -n "${bench_usage_lines}p" "$0" | sed 's/^# \{0,1\}//' >&2
  exit 2
}

bench_parse_args() {
  runs=1
  positional=()
  while (($#)); do
    case "$1" in
      --runs) runs=${2:?--runs needs a value}; shift 2 ;;
      -h|--help) bench_usage ;;
      -*)
        bench_consumed=0
        if declare -F bench_extra_option >/dev/null; then bench_extra_option "$1" "${2-}"; fi
        ((bench_consumed > 0)) || { echo "unknown option $1" >&2; bench_usage; }
        shift "$bench_consumed" ;;
      *) positional+=("$1"); shift ;;
    esac
  done
  [[ "$runs" =~ ^[0-9]+$ ]] && ((runs >= 1)) || bench_usage
}

# The work directory (DEMLINK_BENCH_WORK, default <repo>/bench/work, git-ignored), created.
bench_work_dir() {
  local work=${DEMLINK_BENCH_WORK:-$repo/bench/work}
  mkdir -p "$work"
  echo "$work"
}

# Open MPI refuses root unless told (containers).
bench_allow_mpi_root() {
  if [[ $(id -u) -eq 0 ]]; then export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1; fi
}

# Median of the arguments.
bench_median() {
  python3 -c "import statistics, sys; print(statistics.median(float(x) for x in sys.argv[1:]))" "$@"
}
