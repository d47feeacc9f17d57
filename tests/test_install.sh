#!/usr/bin/env bash
# Packaging test: installs the build under test into a temporary DESTDIR with `meson install`, then builds the
# consumers in tests/consumer/ against the *installed* header and library, found only through the installed
# resurf.pc, exactly as an outside project would:
#   - the header alone compiles as strict C17 (-std=c17 -pedantic -Werror);
#   - consumer.c (C17) and consumer.cpp (C++17), both -Wall -Wextra -pedantic -Werror, linked against the shared
#     library and against the static archive with `pkg-config --static` (so resurf.pc's Libs.private must carry
#     everything libresurf.a needs), run and print "ok";
#   - the shared consumers load libresurf from the DESTDIR; the static ones do not need libresurf.so at all.
# Called by tests/meson.build:
#   test_install.sh BUILD_ROOT SOURCE_ROOT PREFIX LIBDIR CC_ID SANITIZE MESON CC-COMMAND...
set -euo pipefail

build_root=$1 source_root=$2 prefix=$3 libdir=$4 cc_id=$5 sanitize=$6 meson=$7
shift 7
cc=("$@")
# The C++ compiler must match the C one: an ASan library from clang cannot be linked with gcc's runtime.
if [ "$cc_id" = clang ]; then cxx=(clang++); else cxx=(g++); fi

fail() { echo "test_install: FAIL: $*" >&2; exit 1; }

work=$(mktemp -d "${TMPDIR:-/tmp}/resurf-install.XXXXXX")
trap 'rm -rf "$work"' EXIT
destdir=$work/destdir

# A sanitized library needs its runtime in the executable too (ASan must come first in the library list).
san_flags=()
if [ "$sanitize" != none ] && [ -n "$sanitize" ]; then
    san_flags=("-fsanitize=$sanitize")
fi

# --no-rebuild: `meson test` has already built everything; a nested ninja must not race the running tests.
"$meson" install -C "$build_root" --no-rebuild --quiet --destdir "$destdir" >"$work/install.log" 2>&1 ||
    { cat "$work/install.log" >&2; fail "meson install --destdir failed"; }

case $libdir in
    /*) libpath=$destdir$libdir ;;
    *) libpath=$destdir$prefix/$libdir ;;
esac
[ -f "$libpath/pkgconfig/resurf.pc" ] || fail "no resurf.pc installed in $libpath/pkgconfig"

# The sysroot prefixes resurf.pc's -I and -L with the DESTDIR. The ALLOW_SYSTEM switches keep pkg-config from
# dropping -I/usr/include or -L/usr/lib/... (a prefix=/usr build) as system directories, which some versions do
# before applying the sysroot; the check below would then fail instead of the consumers using the real /usr.
export PKG_CONFIG_PATH=$libpath/pkgconfig
export PKG_CONFIG_SYSROOT_DIR=$destdir
export PKG_CONFIG_ALLOW_SYSTEM_CFLAGS=1 PKG_CONFIG_ALLOW_SYSTEM_LIBS=1

version=$(pkg-config --modversion resurf) || fail "pkg-config cannot read the installed resurf.pc"
read -r -a cflags <<<"$(pkg-config --cflags resurf)"
read -r -a libs <<<"$(pkg-config --libs resurf)"
read -r -a static_libs <<<"$(pkg-config --static --libs resurf)"
# -l:libresurf.a makes the linker take the archive although libresurf.so sits next to it; the rest of the
# --static line (Libs.private) is what the archive needs.
static_libs=("${static_libs[@]/#-lresurf/-l:libresurf.a}")
# Every -I and -L must lead into the DESTDIR, and there must be one of each: nothing may come from elsewhere.
have_i=0 have_l=0
for flag in "${cflags[@]}" "${libs[@]}"; do
    case $flag in
        "-I$destdir"/*) have_i=1 ;;
        "-L$destdir"/*) have_l=1 ;;
        -I* | -L*) fail "resurf.pc gives $flag, outside the DESTDIR" ;;
    esac
done
if [ $have_i = 0 ] || [ $have_l = 0 ]; then
    fail "resurf.pc lacks -I or -L: cflags '${cflags[*]}', libs '${libs[*]}'"
fi

c_flags=(-std=c17 -Wall -Wextra -pedantic -Werror "${san_flags[@]}")
cxx_flags=(-std=c++17 -Wall -Wextra -pedantic -Werror "${san_flags[@]}")
consumer=$source_root/tests/consumer

# Each installed header on its own, as strict C17: nothing it needs may come from the includer, and any of them
# brings in the whole API (resurf.h includes the others at its end; each of them includes resurf.h first).
for header in resurf scene preview; do
    [ -f "$destdir$prefix/include/resurf/$header.h" ] || fail "include/resurf/$header.h is not installed"
    printf '#include <resurf/%s.h>\nresurf_preview_options o;\nresurf_mesh *m;\n' "$header" >"$work/header_only.c"
    "${cc[@]}" -std=c17 -pedantic -Wall -Wextra -Werror -fsyntax-only "${cflags[@]}" "$work/header_only.c" ||
        fail "$header.h does not compile on its own as C17 -pedantic"
done

build() { # build OUTPUT COMMAND...: runs COMMAND -o OUTPUT
    local out=$1
    shift
    "$@" -o "$work/$out" || fail "building $out: $*"
}
build c_shared "${cc[@]}" "${c_flags[@]}" "${cflags[@]}" "$consumer/consumer.c" "${libs[@]}"
build c_static "${cc[@]}" "${c_flags[@]}" "${cflags[@]}" "$consumer/consumer.c" "${static_libs[@]}"
build cpp_shared "${cxx[@]}" "${cxx_flags[@]}" "${cflags[@]}" "$consumer/consumer.cpp" "${libs[@]}"
build cpp_static "${cxx[@]}" "${cxx_flags[@]}" "${cflags[@]}" "$consumer/consumer.cpp" "${static_libs[@]}"

for exe in c_shared cpp_shared; do
    # The installed .so has no build-tree rpath: the loader must find it through LD_LIBRARY_PATH in the DESTDIR.
    loaded=$(LD_LIBRARY_PATH=$libpath ldd "$work/$exe" | awk '/libresurf/ {print $3}')
    case $loaded in "$libpath"/libresurf.so.*) ;; *) fail "$exe loads libresurf from '$loaded', not $libpath" ;; esac
    out=$(LD_LIBRARY_PATH=$libpath "$work/$exe" "$version") || fail "$exe exited with $?"
    [ "$out" = ok ] || fail "$exe printed '$out', not 'ok'"
done
for exe in c_static cpp_static; do
    needed=$(readelf -d "$work/$exe" | awk '/NEEDED/ && /libresurf/')
    [ -z "$needed" ] || fail "$exe needs libresurf.so: $needed"
    out=$("$work/$exe" "$version") || fail "$exe exited with $?"
    [ "$out" = ok ] || fail "$exe printed '$out', not 'ok'"
done
echo "installed resurf $version into $destdir; C and C++ consumers, shared and static: ok"
