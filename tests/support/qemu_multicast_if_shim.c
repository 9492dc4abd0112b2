/* Test support for scripts/build-arm64 only, never shipped.
 *
 * qemu-user 7.2 (Debian 12's qemu-user-static) does not emulate setsockopt(IP_MULTICAST_IF)
 * and fails it with ENOPROTOOPT. Fast DDS sets that option on every UDP output channel it
 * opens, so an emulated arm64 process opens none and never discovers anyone. Preloaded into
 * the emulated device only (qemu-aarch64-static -E LD_PRELOAD=...; scripts/arm64-launcher),
 * this lets that one option succeed without effect. The DDS check runs in the isolated
 * namespace, whose only interface is loopback: the default multicast interface is the one
 * there is. A real arm64 board's kernel implements the option; it needs no shim.
 */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <netinet/in.h>
#include <sys/socket.h>

int setsockopt(int fd, int level, int name, const void* value, socklen_t length) {
  static int (*real_setsockopt)(int, int, int, const void*, socklen_t);
  if (real_setsockopt == 0) real_setsockopt = (int (*)(int, int, int, const void*, socklen_t))dlsym(RTLD_NEXT, "setsockopt");
  const int result = real_setsockopt(fd, level, name, value, length);
  if (result != 0 && level == IPPROTO_IP && name == IP_MULTICAST_IF) return 0;
  return result;
}
