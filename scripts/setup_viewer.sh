#!/usr/bin/env bash
# Install what the web viewer needs to build and test: Node.js + npm (to bundle three.js at build time),
# Debian's chromium (headless, for the viewer test), and the npm packages pinned in viewer/package-lock.json.
# Usage: scripts/setup_viewer.sh     (needs root or sudo for apt; safe to run again)
# Without node/npm the build still works: `geotex view` then says the viewer bundle is unavailable.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"

packages=(chromium)
command -v node >/dev/null 2>&1 || packages+=(nodejs)
command -v npm >/dev/null 2>&1 || packages+=(npm)
source "$here/scripts/apt_ensure.sh"
apt_ensure setup_viewer "${packages[@]}"

# npm packages exactly as locked (three, esbuild, playwright-core). Playwright never downloads a browser:
# the test drives /usr/bin/chromium.
cd "$here/viewer"
# Skip `npm ci` when node_modules already matches the lock file (it would reinstall everything).
lock_sum=$(sha256sum package-lock.json | cut -d' ' -f1)
if [ "$(cat node_modules/.geotex-lock 2>/dev/null)" != "$lock_sum" ]; then
  PLAYWRIGHT_SKIP_BROWSER_DOWNLOAD=1 npm ci --no-audit --no-fund
  echo "$lock_sum" > node_modules/.geotex-lock
fi
# The bundle for source-tree use (the CMake build embeds its own copy: viewer/CMakeLists.txt).
npm run build --silent
echo "setup_viewer: node $(node --version), npm packages in viewer/node_modules, $(/usr/bin/chromium --version 2>/dev/null || echo 'chromium missing')"
