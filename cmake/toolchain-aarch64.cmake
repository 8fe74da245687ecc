# Cross build for AArch64 (64-bit ARM) Linux on a Debian 12 x86-64 machine: `./do cross` uses it
# (docs/demosaicking.md, Round 35). Debian's cross GCC (gcc-aarch64-linux-gnu) compiles; the
# libraries are Debian's arm64 packages installed through multiarch (dpkg --add-architecture
# arm64), found with their pkg-config files; the test programs run under qemu-aarch64 (user mode).
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(CMAKE_C_COMPILER aarch64-linux-gnu-gcc)
set(CMAKE_CXX_COMPILER aarch64-linux-gnu-g++)
set(CMAKE_LIBRARY_ARCHITECTURE aarch64-linux-gnu)
set(CMAKE_FIND_ROOT_PATH /usr/aarch64-linux-gnu /usr/lib/aarch64-linux-gnu)
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
# the arm64 packages' .pc files, not the host's (a host library found here fails at link time)
set(ENV{PKG_CONFIG_LIBDIR} /usr/lib/aarch64-linux-gnu/pkgconfig:/usr/share/pkgconfig)
set(ENV{PKG_CONFIG_PATH} "")
# `-L /`: the arm64 dynamic loader and libc of the multiarch packages, which belong together.
# The cross toolchain's own sysroot (-L /usr/aarch64-linux-gnu) has another build of glibc's
# loader; with the multiarch libc.so.6 found first it hangs in the first pthread_create (the
# two builds disagree on the loader's shared state), which is what stalled Round 34c's runs.
set(CMAKE_CROSSCOMPILING_EMULATOR qemu-aarch64 -L /)
