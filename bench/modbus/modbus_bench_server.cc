// hybridtest_modbus_server: a Modbus/TCP lab controller built on libmodbus's server side
// (modbus_mapping_new_start_address, modbus_receive, modbus_reply), serving the default register
// profile of docs/modbus.md with an ideal actuator and a linear specimen:
//   force [N] = stiffness [N/mm] × (position [mm] − p0 [mm]),  position = command.
// The reference peer of bench/bench_modbus_latency.cc and of the 10 s Modbus contract test
// (tests/integration/modbus_ladder_test.cc), where the pymodbus controller
// (tests/transfer/modbus_server.py) would take a minute. One client at a time.
//
//   hybridtest_modbus_server [--listen 127.0.0.1:PORT] [--stiffness N_PER_MM] [--p0-mm MM]
// Port 0 picks a free port. Prints "hybridtest_modbus_server: listening on HOST:PORT" once it
// accepts connections; runs until killed.
#include <arpa/inet.h>
#include <modbus.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <bit>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

namespace {

constexpr int kCommand = 0, kSequence = 2;                            // holding registers
constexpr int kPosition = 0, kForce = 2, kAck = 4, kStatus = 5;       // input registers
constexpr int kEnable = 0, kHold = 1;                                 // coils

// float32 big-endian, high word first (the default profile). Not libmodbus's
// modbus_set_float_abcd: in Debian 12's libmodbus 3.1.6 it swaps the bytes inside each register
// ({0xA041, 0x0000} for 20.0f instead of {0x41A0, 0x0000}), while modbus_get_float_abcd reads
// the standard order.
void SetFloat(std::uint16_t* dest, float value) {
  const auto bits = std::bit_cast<std::uint32_t>(value);
  dest[0] = static_cast<std::uint16_t>(bits >> 16);
  dest[1] = static_cast<std::uint16_t>(bits & 0xFFFF);
}
float GetFloat(const std::uint16_t* src) {
  return std::bit_cast<float>((static_cast<std::uint32_t>(src[0]) << 16) | src[1]);
}

void Update(modbus_mapping_t* m, double stiffness, double p0, std::uint16_t& last_sequence) {
  const int status = (m->tab_bits[kEnable] ? 1 : 0) | (m->tab_bits[kHold] ? 4 : 0);
  m->tab_input_registers[kStatus] = static_cast<std::uint16_t>(status);
  const std::uint16_t sequence = m->tab_registers[kSequence];
  if (sequence == last_sequence) return;
  last_sequence = sequence;
  const float position = GetFloat(m->tab_registers + kCommand);  // ideal actuator
  SetFloat(m->tab_input_registers + kPosition, position);
  SetFloat(m->tab_input_registers + kForce,
           static_cast<float>(stiffness * (static_cast<double>(position) - p0)));
  m->tab_input_registers[kAck] = sequence;
}

}  // namespace

int main(int argc, char** argv) {
  std::string host = "127.0.0.1";
  int port = 5020;
  double stiffness = 5.25, p0 = 0.0;  // [N/mm], [mm]
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string key = argv[i], value = argv[i + 1];
    if (key == "--listen") {
      const auto colon = value.rfind(':');
      host = value.substr(0, colon);
      port = std::atoi(value.c_str() + colon + 1);
    } else if (key == "--stiffness") {
      stiffness = std::atof(value.c_str());
    } else if (key == "--p0-mm") {
      p0 = std::atof(value.c_str());
    } else {
      std::fprintf(stderr, "hybridtest_modbus_server: unknown option %s\n", key.c_str());
      return 2;
    }
  }
  modbus_t* ctx = modbus_new_tcp(host.c_str(), port);
  modbus_mapping_t* map = modbus_mapping_new_start_address(0, 16, 0, 0, 0, 16, 0, 16);
  if (ctx == nullptr || map == nullptr) {
    std::fprintf(stderr, "hybridtest_modbus_server: %s\n", modbus_strerror(errno));
    return 1;
  }
  const int server = modbus_tcp_listen(ctx, 1);
  if (server < 0) {
    std::fprintf(stderr, "hybridtest_modbus_server: cannot listen on %s:%d: %s\n", host.c_str(),
                 port, modbus_strerror(errno));
    return 1;
  }
  sockaddr_in bound{};
  socklen_t length = sizeof bound;
  getsockname(server, reinterpret_cast<sockaddr*>(&bound), &length);
  std::printf("hybridtest_modbus_server: listening on %s:%d (ideal actuator, specimen %g N/mm, "
              "p0 %g mm)\n", host.c_str(), ntohs(bound.sin_port), stiffness, p0);
  std::fflush(stdout);
  std::uint16_t last_sequence = 0;
  std::uint8_t request[MODBUS_TCP_MAX_ADU_LENGTH];
  int listening = server;
  for (;;) {
    if (modbus_tcp_accept(ctx, &listening) < 0) continue;
    for (;;) {
      const int n = modbus_receive(ctx, request);
      if (n == 0) continue;  // a request for another unit: ignored
      if (n < 0) break;      // the client went away
      modbus_reply(ctx, request, n, map);
      Update(map, stiffness, p0, last_sequence);
    }
    close(modbus_get_socket(ctx));
    modbus_set_socket(ctx, -1);
  }
}
