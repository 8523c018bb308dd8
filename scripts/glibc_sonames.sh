# glibc's shared libraries, by soname: a relocatable bundle never carries them (they must match the
# machine's ld.so). Sourced by scripts/bundle.sh and tests/bundle/bundle_test.sh.
is_glibc() {
  case "$1" in
    ld-linux*.so*|libc.so.*|libm.so.*|libmvec.so.*|libpthread.so.*|libdl.so.*|librt.so.*|\
    libresolv.so.*|libutil.so.*|libanl.so.*|libnsl.so.*|libcrypt.so.*) return 0 ;;
  esac
  return 1
}
