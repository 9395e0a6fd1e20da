#!/usr/bin/env bash
# The web page's end-to-end check (docs/web.md): builds the page
# (scripts/web-build.sh), installs Debian's Chromium and the npm packages
# when missing, and runs the Playwright suite in web/tests against the page
# served by the release `morphogen serve`. CI passes the binary it built as
# MORPHOGEN_RELEASE_BIN; locally the default is target/release/morphogen.
set -euo pipefail
cd "$(dirname "$0")/.."

morphogen="${MORPHOGEN_RELEASE_BIN:-$PWD/target/release/morphogen}"
if [[ ! -x "$morphogen" ]]; then
    echo "web-check: no release binary at $morphogen (cargo build --release -p morphogen-cli, or set MORPHOGEN_RELEASE_BIN)" >&2
    exit 2
fi
export MORPHOGEN_RELEASE_BIN="$morphogen"

if [[ ! -x /usr/bin/chromium ]]; then
    echo "==> web: installing Debian's Chromium"
    as_root() { if [ "$(id -u)" -eq 0 ]; then "$@"; else sudo "$@"; fi; }
    as_root apt-get update -qq
    as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq chromium
fi

bash scripts/web-build.sh

echo "==> web: Playwright end-to-end tests (Chromium headless)"
cd web
# The tests drive /usr/bin/chromium: Playwright's own browsers are not
# downloaded.
PLAYWRIGHT_SKIP_BROWSER_DOWNLOAD=1 npx --no-install playwright test
