# Sourced by scripts/setup.sh and scripts/test.sh: installs the Debian packages a command needs.
#
# install_missing_debian_packages TAG [apt-get install option ...] -- PACKAGE ...
# installs those of PACKAGE not yet installed (apt-get, through sudo unless root), saying so
# after TAG; does nothing when all are there.
install_missing_debian_packages() {
  local tag=$1 options=() missing=() pkg sudo=""
  shift
  while [ "$#" -gt 0 ] && [ "$1" != "--" ]; do options+=("$1"); shift; done
  shift
  for pkg in "$@"; do
    dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q "install ok installed" || missing+=("$pkg")
  done
  ((${#missing[@]})) || return 0
  echo "$tag installing Debian packages: ${missing[*]}"
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq "${options[@]}" "${missing[@]}" >/dev/null
}
