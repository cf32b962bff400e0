#!/bin/sh
# copcjs_setup.sh THIRD_PARTY DIR: installs the JavaScript test clients pinned in
# THIRD_PARTY/npm-tests.json (copc.js and laz-perf; geotiff.js; exact versions from
# npm-tests-lock.json) into DIR/node_modules from the npm registry, once: a DIR whose
# manifest and lockfile equal the pinned ones is left as it is. The ctest fixture "copcjs"
# of the copc.js and geotiff.js tests.
set -eu
src="$1"
dir="$2"
if [ -f "$dir/node_modules/.ladarvr-installed" ] &&
   cmp -s "$src/npm-tests.json" "$dir/package.json" &&
   cmp -s "$src/npm-tests-lock.json" "$dir/package-lock.json"; then
  echo "copcjs_setup: $dir is up to date"
  exit 0
fi
command -v npm >/dev/null || { echo "copcjs_setup: npm is not installed (third_party/packages-build.txt lists it)" >&2; exit 1; }
rm -rf "$dir/node_modules"
mkdir -p "$dir"
cp "$src/npm-tests.json" "$dir/package.json"
cp "$src/npm-tests-lock.json" "$dir/package-lock.json"
cd "$dir"
# The cache stays in the build folder, not in $HOME; no audit or funding requests.
npm_config_cache="$dir/.npm-cache" timeout 300 npm ci --no-audit --no-fund --ignore-scripts ||
  { echo "copcjs_setup: npm ci failed; the npm registry must be reachable to set up the copc.js tests" >&2; exit 1; }
touch node_modules/.ladarvr-installed
echo "copcjs_setup: installed $(node -p 'require("./node_modules/copc/package.json").version' 2>/dev/null || echo '?') of copc and $(node -p 'require("./node_modules/geotiff/package.json").version' 2>/dev/null || echo '?') of geotiff into $dir"
