#!/usr/bin/env bash
# Install the Debian packages the tests need beyond the venv, if any is missing:
#   xvfb      a virtual X display: the Eye's window is tested under it (its -fbdir framebuffer file
#             is the screenshot)
#   libxtst6  X's XTest client library: the window test clicks and types through it (ctypes)
#   chromium  headless Chromium: the Eye's web page is tested in it (DevTools on a pipe)
# A quick no-op (dpkg-query only) when all are installed; `apt-get update` runs only when one is
# missing. Needs root (or password-less sudo) and apt-get; says so clearly when they are not there.
# Called by `make test` (the demo needs none of these).
set -euo pipefail

packages=(xvfb libxtst6 chromium)

missing=()
for package in "${packages[@]}"; do
  status=$(dpkg-query -W -f='${Status}' "$package" 2>/dev/null || true)
  [ "$status" = "install ok installed" ] || missing+=("$package")
done
[ ${#missing[@]} -eq 0 ] && exit 0

echo "setup_system: installing ${missing[*]} (Debian packages the tests need)"
if ! command -v apt-get >/dev/null 2>&1; then
  echo "setup_system: apt-get not found: install ${missing[*]} (Debian/Ubuntu names) by hand" >&2
  exit 1
fi
sudo=()
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1 && sudo -n true 2>/dev/null; then
    sudo=(sudo -n)
  else
    echo "setup_system: not root and no password-less sudo: run" \
         "'apt-get install --no-install-recommends ${missing[*]}' as root" >&2
    exit 1
  fi
fi
export DEBIAN_FRONTEND=noninteractive
"${sudo[@]}" apt-get update -qq
"${sudo[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
