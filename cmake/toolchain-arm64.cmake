# Cross build for rescuer devices on arm64 (scripts/build-arm64): Debian's cross toolchain
# (crossbuild-essential-arm64) and the :arm64 multiarch -dev packages installed beside the
# amd64 ones (scripts/install-deps --arm64). Executables and tests run under qemu-user.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(CMAKE_C_COMPILER aarch64-linux-gnu-gcc)
set(CMAKE_CXX_COMPILER aarch64-linux-gnu-g++)
set(CMAKE_LIBRARY_ARCHITECTURE aarch64-linux-gnu)
# Tests are listed and run through qemu (no binfmt needed), with the multiarch arm64 libraries.
set(CMAKE_CROSSCOMPILING_EMULATOR qemu-aarch64-static)
# pkg-config: the arm64 .pc files, and the architecture-independent ones.
set(ENV{PKG_CONFIG_LIBDIR} /usr/lib/aarch64-linux-gnu/pkgconfig:/usr/share/pkgconfig)
set(ENV{PKG_CONFIG_PATH} "")
