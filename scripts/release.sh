#!/usr/bin/env bash
# Builds the release artifacts of pmacstream into OUT_DIR (default artifacts/release) and prints their paths:
#   pmacstream-VERSION-linux-x64.tar.gz  Native AOT: the pmacstream binary, with the native libraries it loads on
#                                        demand beside it (libe_sqlite3.so: job store; libSkiaSharp.so: preview;
#                                        libSystem.IO.Ports.Native.so: serial ports) and samples/
#   pmacstream-VERSION-win-x64.zip       pmacstream.exe, self-contained single file (the .NET runtime and the native
#                                        libraries inside it), and samples/. Native AOT cannot cross-compile, so the
#                                        Windows build is a self-contained JIT build.
#   pmacstream.VERSION.nupkg             the .NET tool: dotnet tool install -g --add-source OUT_DIR pmacstream
# Usage: scripts/release.sh [OUT_DIR]     ONLY="linux-x64 win-x64 tool" (the default) picks what is built.
# Warnings are errors here as in every build; a failed step stops the script with its exit code.
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=${1:-artifacts/release}
mkdir -p "$OUT"
OUT=$(cd "$OUT" && pwd)
ONLY=${ONLY:-linux-x64 win-x64 tool}
WORK=$(mktemp -d "${TMPDIR:-/tmp}/pmacstream-release.XXXXXX")
trap 'rm -rf "$WORK"' EXIT
VERSION=$(dotnet msbuild src/PmacStream.Cli/PmacStream.Cli.csproj -nologo -getProperty:Version)
export DOTNET_CLI_TELEMETRY_OPTOUT=1 DOTNET_NOLOGO=1

# stage RID PUBLISH_DIR FILE...: copies the named files and samples/ into a folder named like the archive.
stage() {
  local rid=$1 from=$2; shift 2
  local dir="$WORK/pmacstream-$VERSION-$rid"
  mkdir -p "$dir"
  for f in "$@"; do cp "$from/$f" "$dir/"; done
  cp -r "$from/samples" "$dir/"
  cp README.md "$dir/"
  echo "$dir"
}

for what in $ONLY; do
  case "$what" in
    linux-x64)
      dotnet publish src/PmacStream.Cli -c Release -r linux-x64 -p:PublishAot=true -o "$WORK/publish-linux-x64" -nologo -v q >&2
      dir=$(stage linux-x64 "$WORK/publish-linux-x64" pmacstream libe_sqlite3.so libSkiaSharp.so libSystem.IO.Ports.Native.so)
      tar -C "$WORK" -czf "$OUT/pmacstream-$VERSION-linux-x64.tar.gz" "$(basename "$dir")"
      echo "$OUT/pmacstream-$VERSION-linux-x64.tar.gz"
      ;;
    win-x64)
      dotnet publish src/PmacStream.Cli -c Release -r win-x64 --self-contained -p:PublishSingleFile=true \
        -p:IncludeNativeLibrariesForSelfExtract=true -o "$WORK/publish-win-x64" -nologo -v q >&2
      dir=$(stage win-x64 "$WORK/publish-win-x64" pmacstream.exe)
      rm -f "$OUT/pmacstream-$VERSION-win-x64.zip"
      (cd "$WORK" && zip -qr "$OUT/pmacstream-$VERSION-win-x64.zip" "$(basename "$dir")")
      echo "$OUT/pmacstream-$VERSION-win-x64.zip"
      ;;
    tool)
      dotnet pack src/PmacStream.Cli -c Release -o "$OUT" -nologo -v q >&2
      echo "$OUT/pmacstream.$VERSION.nupkg"
      ;;
    *) echo "release: unknown target '$what' (linux-x64, win-x64, tool)" >&2; exit 2 ;;
  esac
done
