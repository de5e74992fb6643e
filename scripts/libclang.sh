# Sourced by setup.sh and scripts/test_libclang.sh: is there a libclang that bindgen can load?
#
# bindgen (fmi-sys's build script) loads libclang at run time through clang-sys (feature `runtime`), which
# accepts, in the directories it searches, the file names `libclang.so`, `libclang-*.so`, `libclang.so.*` and
# `libclang-*.so.*`, and drops every name containing `-cpp.` (libclang-cpp.so.N is the C++ library, which
# Debian installs with clang itself: matching it is how the old `ldconfig -p | grep libclang` was fooled).

# libclang_present PATH...: prints "present" (status 0) if one of the paths is a libclang that clang-sys
# accepts, else "missing" (status 1). Only the names are judged, so the test can feed it any layout.
libclang_present() {
    local path name
    for path in "$@"; do
        name=${path##*/}
        case $name in
            *-cpp.*) continue ;;
            libclang.so | libclang-*.so | libclang.so.* | libclang-*.so.*)
                echo present
                return 0
                ;;
        esac
    done
    echo missing
    return 1
}

# libclang_candidates: every libclang* file in the directories clang-sys searches on Linux (its DIRECTORIES_LINUX
# globs, plus LIBCLANG_PATH, `llvm-config --prefix`/lib* and LD_LIBRARY_PATH), one per line.
libclang_candidates() {
    local dirs=(/usr/local/llvm*/lib* /usr/local/lib*/*/* /usr/local/lib*/* /usr/local/lib* /usr/lib*/*/* /usr/lib*/* /usr/lib*)
    if [ -n "${LIBCLANG_PATH:-}" ]; then
        # clang-sys then searches only there: the library file itself, or a directory.
        if [ -f "$LIBCLANG_PATH" ]; then
            echo "$LIBCLANG_PATH"
            return 0
        fi
        dirs=("$LIBCLANG_PATH")
    else
        if command -v llvm-config >/dev/null 2>&1; then
            dirs+=("$(llvm-config --prefix)"/lib*)
        fi
        local IFS=:
        dirs+=(${LD_LIBRARY_PATH:-})
    fi
    local d f
    for d in "${dirs[@]}"; do
        [ -d "$d" ] || continue
        for f in "$d"/libclang*.so*; do
            [ -e "$f" ] && echo "$f"
        done
    done
    return 0
}
