# Shared by the e2e scripts (sourced, not a test itself: ctest runs tests/e2e/*.sh only).

# require_tools TOOL...: skip the test (exit 77) unless every tool is built in $tools.
require_tools() {
  local tool
  for tool in "$@"; do
    [[ -x $tools/$tool ]] || { echo "SKIP: $tool is not built"; exit 77; }
  done
}

# final_files DIR: its files under final names (hidden temporaries of atomic writes left out),
# relative to DIR, sorted; nothing if DIR does not exist.
final_files() {
  [[ -d $1 ]] || return 0
  (cd "$1" && find . -type f ! -name '.*' | sed 's|^\./||' | sort)
}
