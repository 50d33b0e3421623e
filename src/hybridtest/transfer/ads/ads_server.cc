// See ads_server.h: connections, routes and the ADS services. The PLC program (the cycle)
// is in ads_server_cycle.cc.
#include "hybridtest/transfer/ads/ads_server.h"

#include <fmt/core.h>
#include <poll.h>

#include <algorithm>
#include <chrono>

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/ads/ads_link.h"

namespace hybridtest::transfer::ads {
namespace {

using Clock = std::chrono::steady_clock;

// The longest AMS/TCP message served: a prefix and 64 KiB (sum commands included). [bytes]
constexpr std::size_t kMaxMessage = kPrefixSize + (1u << 16);

// The codec for the ServerLoop: a message is the 6-byte prefix and `length` bytes after it.
std::size_t MessageSize(const ServerLoop::Connection&, std::span<const std::uint8_t> bytes) {
  if (bytes.size() < kPrefixSize) return kPrefixSize;
  return kPrefixSize + DecodePrefix(bytes.first(kPrefixSize)).length;
}

const std::string& CheckedHost(const AdsServerOptions& o) {
  if (o.program == PlcProgram::kPHybrid) {
    if (!(o.cycle_time >= 1e-3 && o.cycle_time <= 1.0) || !(o.watchdog > 0.0)) {
      throw ConfigError(fmt::format("ADS emulator: cycle time {} s and watchdog {} s: expected a "
                                    "cycle of 0.001 to 1 s and a watchdog above 0 s",
                                    o.cycle_time, o.watchdog));
    }
    if (!o.faults.empty()) {
      throw ConfigError("--inject: test faults apply to the instant PLC program only; leave "
                        "out --plc-program p_hybrid, or --inject");
    }
  }
  if (o.routes.empty() && !IsLoopbackHost(o.host)) {
    throw ConfigError(fmt::format(
        "--listen {}: an ADS server off loopback serves only the AmsNetIds it is told to route, "
        "as a TwinCAT router does: give --route NETID (one per client, e.g. --route "
        "192.168.0.5.1.1)", o.host));
  }
  return o.host;
}

}  // namespace

AdsRoute ParseAdsRoute(const std::string& text, const std::string& where) {
  const auto at = text.find('@');
  const auto id = ParseAmsNetId(text.substr(0, at));
  const std::string address = at == std::string::npos ? "" : text.substr(at + 1);
  if (!id || (at != std::string::npos && address.empty())) {
    throw ConfigError(fmt::format("{} {}: expected NETID or NETID@ADDRESS, an AmsNetId (six "
                                  "numbers 0..255 joined by dots, e.g. 192.168.0.5.1.1) and the "
                                  "client's numeric address (default: the AmsNetId's first four "
                                  "numbers)", where, text));
  }
  if (!address.empty()) return {*id, address};
  const auto& b = id->bytes;
  return {*id, fmt::format("{}.{}.{}.{}", b[0], b[1], b[2], b[3])};
}

AdsFault ParseAdsFault(const std::string& text, const std::string& where) {
  static const std::pair<const char*, AdsFault::Kind> kKinds[] = {
      {"fault", AdsFault::Kind::kFault},       {"silence", AdsFault::Kind::kSilence},
      {"close", AdsFault::Kind::kClose},       {"ads_error", AdsFault::Kind::kAdsError},
      {"holding", AdsFault::Kind::kHolding}};
  const auto at = text.find('@');
  const std::string kind = text.substr(0, at);
  for (const auto& [name, k] : kKinds) {
    if (kind != name || at == std::string::npos) continue;
    try {
      std::size_t used = 0;
      const long n = std::stol(text.substr(at + 1), &used);
      if (n >= 1 && used == text.size() - at - 1) return {k, n};
    } catch (const std::exception&) {
    }
  }
  throw ConfigError(fmt::format("{} {}: expected KIND@N with N ≥ 1 the command number and KIND "
                                "one of fault, silence, close, ads_error, holding", where, text));
}

void UseBenchSafety(AdsServerOptions& o, const EmulatedBenchSpec& spec) {
  o.limits = spec.actuators[0].safety;
  o.start_positions.clear();
  for (const auto& a : spec.actuators) o.start_positions.push_back(a.initial_position);
  if (spec.coupled_safety) {
    o.actuator_stiffness = spec.stiffness;
  } else {
    o.initial_stiffness = spec.stiffness(0, 0);
  }
}

AdsServer::AdsServer(TransferSystem& bench, AdsServerOptions options)
    : bench_(bench),
      options_(std::move(options)),
      listener_(CheckedHost(options_), options_.port),
      image_([&] {
        AdsProfile p = options_.profile;
        p.actuators = bench.num_actuators();
        p.units = bench.bench_units();
        return p;
      }()),
      gate_(std::vector<SafetyLimits>(static_cast<std::size_t>(bench.num_actuators()),
                                      options_.limits)),
      loop_(listener_,
            {.max_connections = options_.max_connections,
             .max_frame_bytes = kMaxMessage,
             .frame_timeout = options_.message_timeout,
             .idle_timeout = options_.idle_timeout,
             .send_timeout = options_.message_timeout,
             .poll_ms = options_.program == PlcProgram::kPHybrid
                            ? static_cast<int>(options_.cycle_time * 1000.0)
                            : 100},
            MessageSize,
            {.opened =
                 [this](Client& c) {
                   c.established = true;  // ADS has no opening: every packet stands alone
                   Log(fmt::format("client {} connected from {}", c.id, c.peer));
                   return true;
                 },
             .frame = [this](Client& c, std::span<const std::uint8_t> m) { return HandleMessage(c, m); },
             .closed = [this](const Client& c, const ServerLoop::Closing& closing) {
               Closed(c, closing.why, closing.commander);
             }},
            [this](const std::string& line) { Log(line); }) {
  options_.profile.actuators = bench.num_actuators();
  options_.profile.units = bench.bench_units();
  for (int k = 0; k < gate_.size(); ++k) {
    const auto i = static_cast<std::size_t>(k);
    if (i < options_.start_positions.size()) gate_.monitor(k).SetStartPosition(options_.start_positions[i]);
    if (options_.initial_stiffness) gate_.monitor(k).SetInitialStiffness(*options_.initial_stiffness);
  }
  if (options_.actuator_stiffness) UseCoupledStiffness(gate_, *options_.actuator_stiffness);
}

AdsServer::~AdsServer() = default;

std::string AdsServer::DescribeRoutes() const {
  std::string routes;
  for (const AdsRoute& r : options_.routes) {
    routes += fmt::format("{}{} from {}", routes.empty() ? "" : ", ", FormatAmsNetId(r.net_id), r.address);
  }
  return fmt::format("AmsNetId {}, AMS port {}, routes: {}", FormatAmsNetId(options_.address.net_id),
                     options_.address.port, routes.empty() ? "any (loopback)" : routes);
}

void AdsServer::Log(const std::string& line) const {
  if (options_.log) options_.log(line);
}

void AdsServer::Serve() {
  bench_.Activate();
  bench_active_ = true;
  // The PLC publishes where the actuators are before the first command.
  const double metres = bench_.bench_units().metres_per_length_unit;
  std::vector<double> position(static_cast<std::size_t>(bench_.num_actuators()), 0.0);
  std::vector<double> force(position.size(), 0.0);
  if (auto now = bench_.ReadAll()) {
    for (std::size_t k = 0; k < position.size(); ++k) {
      position[k] = (*now)[k].position;
      force[k] = (*now)[k].force;
    }
  } else {
    for (std::size_t k = 0; k < position.size() && k < options_.start_positions.size(); ++k) {
      position[k] = options_.start_positions[k] / metres;
    }
  }
  image_.SetReals(kPosition, position);
  image_.SetReals(kForce, force);
  image_.SetReals(kCommand, position);
  actual_ = {position, force};
  if (options_.program == PlcProgram::kPHybrid) {
    while (!stop_.load()) {  // the PLC task: its cycle after what the clients sent meanwhile
      loop_.Turn();
      ProgramCycle();
    }
    loop_.CloseAll("the server stops");
  } else {
    loop_.Serve(stop_);
  }
  bench_.Deactivate();
}

void AdsServer::Closed(const Client& client, const std::string& why, bool commander) {
  image_.ReleaseAll(client.id);
  Log(fmt::format("client {} dropped: {}", client.id, why));
  if (commander && options_.program == PlcProgram::kInstant) {  // P_Hybrid: its watchdog
    image_.SetBool(kHold, true);
    image_.SetBool(kHolding, true);
    last_hold_ = true;
    HoldBench("the client that drove the PLC went away; bHold set, as a PLC's watchdog would");
  }
}

bool AdsServer::HandleMessage(Client& client, std::span<const std::uint8_t> message) {
  const Prefix prefix = DecodePrefix(message.first(kPrefixSize));
  const std::span<const std::uint8_t> body = message.subspan(kPrefixSize);
  std::vector<std::uint8_t> answer;
  bool close = false;
  if (prefix.reserved == kTcpPortConnect) {
    // A client without a router asks for an AMS address: its IPv4 address and a port.
    const AmsNetId id = EndpointNetId(client.socket.fd(), true);
    std::vector<std::uint8_t> data(id.bytes.begin(), id.bytes.end());
    PutU16(data, static_cast<std::uint16_t>(32904 + client.id));
    answer = EncodeRouterMessage(kTcpPortConnect, data);
  } else if (prefix.reserved == kTcpAmsCommand) {
    try {
      answer = Answer(client, DecodePacket(body), close);
    } catch (const TransferError& e) {
      Log(fmt::format("client {}: garbled AMS packet: {}", client.id, e.what()));
      return false;
    }
  } else if (prefix.reserved == kTcpPortClose) {
    Log(fmt::format("client {} closed its AMS port", client.id));  // a router drops it then
    return false;
  } else {
    return true;  // other router messages need no answer
  }
  if (!answer.empty() && !loop_.Send(client, answer)) close = true;
  return !close;
}

std::vector<std::uint8_t> AdsServer::Answer(Client& client, const AmsPacket& request,
                                            bool& close) {
  const AmsHeader& h = request.header;
  if (!options_.routes.empty()) {
    const auto route = std::find_if(options_.routes.begin(), options_.routes.end(),
                                    [&](const AdsRoute& r) { return r.net_id == h.source.net_id; });
    const std::string id = FormatAmsNetId(h.source.net_id);
    if (route == options_.routes.end()) {
      Log(fmt::format("refused AmsNetId {} from {}: no route (give --route {}@{} to serve it)",
                      id, client.peer, id, client.peer));
      close = true;
      return {};
    }
    if (route->address != client.peer) {
      Log(fmt::format("refused AmsNetId {} from {}: its route names address {} (a client "
                      "claiming another's AmsNetId; --route {}@ADDRESS names the address)",
                      id, client.peer, route->address, id));
      close = true;
      return {};
    }
  }
  AmsPacket answer;
  answer.header = h;
  answer.header.target = h.source;
  answer.header.source = h.target;
  answer.header.state_flags = kFlagResponse;
  if (h.target.net_id != options_.address.net_id) {
    answer.header.error = kErrTargetMachineNotFound;
    return EncodePacket(answer);
  }
  if (h.target.port != options_.address.port) {
    answer.header.error = kErrTargetPortNotFound;
    return EncodePacket(answer);
  }
  try {
    switch (h.command) {
      case Command::kReadDeviceInfo:
        answer.data = EncodeDeviceInfo({0, 3, 1, 4024, "Plc30 App"});
        break;
      case Command::kReadState:
        answer.data = EncodeStateResponse({0, options_.ads_state, 0});
        break;
      case Command::kRead: {
        const IndexRequest r = DecodeReadRequest(request.data);
        const DataResponse d = image_.Read(r.group, r.offset, r.read_length);
        answer.data = EncodeDataResponse(d.result, d.data);
        break;
      }
      case Command::kWrite: {
        const IndexRequest r = DecodeWriteRequest(request.data);
        if (r.group != kGroupReleaseHandle && !MayWrite(client)) {
          answer.data = EncodeResultResponse(kErrInvalidAccess);
          break;
        }
        std::uint32_t result = image_.Write(r.group, r.offset, r.data, client.id);
        if (result == 0 && r.group != kGroupReleaseHandle) result = Cycle(close);
        answer.data = EncodeResultResponse(result);
        break;
      }
      case Command::kReadWrite:
        answer.data = AnswerReadWrite(client, DecodeReadWriteRequest(request.data), close);
        break;
      default:
        answer.data = EncodeResultResponse(kErrServiceNotSupported);
    }
  } catch (const TransferError& e) {
    Log(fmt::format("client {}: {}", client.id, e.what()));
    answer.data = EncodeResultResponse(kErrInvalidSize);
  }
  return EncodePacket(answer);
}

bool AdsServer::MayWrite(const Client& client) {
  if (loop_.Claim(client.id)) return true;
  Log(fmt::format("refused a write from client {} ({}): client {} commands the PLC; others may "
                  "only read", client.id, client.peer, loop_.commander()));
  return false;
}

std::vector<std::uint8_t> AdsServer::AnswerReadWrite(Client& client, const IndexRequest& r,
                                                     bool& close) {
  if (r.group == kGroupSumRead) {
    const std::vector<SubRequest> items = DecodeSumRead(r.offset, r.data);
    std::vector<DataResponse> answers;
    for (const SubRequest& s : items) answers.push_back(image_.Read(s.group, s.offset, s.length));
    return EncodeDataResponse(0, EncodeSumReadAnswer(answers, items));
  }
  if (r.group == kGroupSumWrite) {
    if (!MayWrite(client)) return EncodeResultResponse(kErrInvalidAccess);
    const std::vector<SubRequest> items = DecodeSumWrite(r.offset, r.data);
    std::vector<std::uint32_t> results;
    for (const SubRequest& s : items) results.push_back(image_.Write(s.group, s.offset, s.data, client.id));
    const std::uint32_t cycle = Cycle(close);
    if (cycle != 0) return EncodeResultResponse(cycle);
    return EncodeDataResponse(0, EncodeSumWriteAnswer(results));
  }
  const DataResponse d = image_.ReadWrite(r.group, r.offset, r.read_length, r.data, client.id);
  return EncodeDataResponse(d.result, d.data);
}

}  // namespace hybridtest::transfer::ads
