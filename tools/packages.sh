# Sourced by the set-up scripts: install_missing LABEL PACKAGE... installs with apt-get the Debian packages that are
# not installed yet, plus Node.js and npm when their commands are missing (a machine may carry Node.js from
# elsewhere: nodesource bundles npm, and Debian's npm would conflict with it). Quiet when nothing is missing.
install_missing() {
  local label=$1 p
  shift
  local missing=()
  for p in "$@"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || missing+=("$p")
  done
  command -v node >/dev/null || missing+=(nodejs)
  command -v npm >/dev/null || missing+=(npm)
  if [ ${#missing[@]} -gt 0 ]; then
    echo "$label: installing ${missing[*]}" >&2
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -qq >/dev/null
    apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
  fi
}
