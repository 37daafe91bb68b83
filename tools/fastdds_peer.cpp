// A Fast DDS participant that prints each participant discovery event with a monotonic time
// stamp (s): "<t> discovered", "<t> removed" (the peer said it left), "<t> dropped" (its lease ran
// out). Usage: fastdds_peer DOMAIN SECONDS. Built by tools/fastdds_leave.py.
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/domain/DomainParticipantListener.hpp>
#include <fastdds/rtps/transport/UDPv4TransportDescriptor.h>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <thread>
using namespace eprosima::fastdds::dds;
using eprosima::fastrtps::rtps::ParticipantDiscoveryInfo;
static double now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }
struct L : DomainParticipantListener {
  void on_participant_discovery(DomainParticipant*, ParticipantDiscoveryInfo&& info) override {
    const char* s = "?";
    switch (info.status) {
      case ParticipantDiscoveryInfo::DISCOVERED_PARTICIPANT: s = "discovered"; break;
      case ParticipantDiscoveryInfo::REMOVED_PARTICIPANT: s = "removed"; break;
      case ParticipantDiscoveryInfo::DROPPED_PARTICIPANT: s = "dropped"; break;
      default: s = "changed";
    }
    std::printf("%.3f %s\n", now(), s); std::fflush(stdout);
  }
};
int main(int argc, char** argv) {
  int domain = std::atoi(argv[1]); double seconds = std::atof(argv[2]);
  L listener;
  DomainParticipantQos qos = PARTICIPANT_QOS_DEFAULT;
  auto* p = DomainParticipantFactory::get_instance()->create_participant(domain, qos, &listener);
  std::printf("%.3f ready\n", now()); std::fflush(stdout);
  std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
  DomainParticipantFactory::get_instance()->delete_participant(p);
}
