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

# install_packages PACKAGE...: installs the Debian packages that are missing (apt-get as root,
# else sudo -n); fails when that is not possible (the caller then skips with exit 77). Tests run
# in parallel, so apt-get waits up to 10 minutes for another test's install to release dpkg's lock
# instead of failing at once.
install_packages() {
  local package missing=()
  for package in "$@"; do
    [[ $(dpkg-query -W -f='${Status}' "$package" 2>/dev/null) == "install ok installed" ]] || missing+=("$package")
  done
  [[ ${#missing[@]} -eq 0 ]] && return 0
  local sudo_cmd=()
  [[ $(id -u) -eq 0 ]] || sudo_cmd=(sudo -n)
  echo "installing ${missing[*]} (apt-get)"
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get -o DPkg::Lock::Timeout=600 install -y -qq --no-install-recommends "${missing[@]}" \
    > /dev/null 2>&1 ||
    { DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get -o DPkg::Lock::Timeout=600 update -qq > /dev/null 2>&1 &&
      DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get -o DPkg::Lock::Timeout=600 install -y -qq --no-install-recommends "${missing[@]}" \
        > /dev/null 2>&1; }
}
