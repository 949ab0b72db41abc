#!/usr/bin/env bash
# Makes `apt-get source` work: when no deb-src entry is configured, adds one for Debian 12
# (bookworm, its updates and security) in /etc/apt/sources.list.d/demlink-deb-src.sources
# and updates the package lists. Idempotent: does nothing when any deb-src entry exists.
# Run by scripts/install_deps.sh; the protobuf source builds (scripts/win64_protobuf.sh,
# scripts/build_pic_protobuf.sh) need it.
set -euo pipefail
if grep -rqsE '^deb-src|^Types:.*deb-src' /etc/apt/sources.list /etc/apt/sources.list.d/; then
  exit 0
fi
echo "ensure_deb_src: adding a deb-src entry for bookworm"
SUDO=""
if [[ $(id -u) -ne 0 ]]; then SUDO="sudo"; fi
$SUDO tee /etc/apt/sources.list.d/demlink-deb-src.sources > /dev/null <<'SOURCES'
Types: deb-src
URIs: http://deb.debian.org/debian
Suites: bookworm bookworm-updates
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg

Types: deb-src
URIs: http://deb.debian.org/debian-security
Suites: bookworm-security
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg
SOURCES
$SUDO apt-get update -qq
