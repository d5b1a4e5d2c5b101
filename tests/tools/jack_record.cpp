// A JACK test client for `maille play` (tests/cli_play_jack.sh): waits for the player's output
// ports, connects them to its inputs, switches the server to freewheel (the graph runs as fast
// as it can, with no deadline: nothing is dropped) and records FRAMES frames, written as a
// float32 WAV. With --midi-to, it also sends MIDI events through a JACK MIDI output port at
// given recorded frames (note-on, control change).
//
//   jack_record --from CLIENT --channels N --frames F --out FILE.wav
//               [--midi-to PORT] [--note FRAME:NOTE:VELOCITY] [--cc FRAME:NUMBER:VALUE]
// Prints "recorded F frames, period P" and, per MIDI event, "midi at frame X".
#include <jack/jack.h>
#include <jack/midiport.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include "maille/wav.hpp"

namespace {

struct Event {
  std::uint64_t frame;
  unsigned char bytes[3];
  bool sent = false;
};

struct Recorder {
  jack_client_t* client = nullptr;
  std::vector<jack_port_t*> in;
  jack_port_t* midi = nullptr;
  std::vector<std::vector<float>> data;
  std::uint64_t want = 0;
  std::atomic<std::uint64_t> got{0};
  std::atomic<bool> freewheeling{false};
  std::vector<Event> events;
};

int process(jack_nframes_t n, void* arg) {
  auto* r = static_cast<Recorder*>(arg);
  void* midi = r->midi ? jack_port_get_buffer(r->midi, n) : nullptr;
  if (midi) jack_midi_clear_buffer(midi);
  if (!r->freewheeling.load()) return 0;
  const std::uint64_t got = r->got.load();
  if (got >= r->want) return 0;
  const std::uint64_t take = std::min<std::uint64_t>(n, r->want - got);
  for (std::size_t c = 0; c < r->in.size(); ++c) {
    const auto* x = static_cast<const float*>(jack_port_get_buffer(r->in[c], n));
    r->data[c].insert(r->data[c].end(), x, x + take);
  }
  for (Event& e : r->events)
    if (!e.sent && midi && e.frame < got + n) {
      const auto offset = static_cast<jack_nframes_t>(e.frame > got ? e.frame - got : 0);
      jack_midi_event_write(midi, offset, e.bytes, 3);
      e.sent = true;
    }
  r->got.store(got + take);
  return 0;
}

void on_freewheel(int starting, void* arg) {
  static_cast<Recorder*>(arg)->freewheeling.store(starting != 0);
}

bool wait_for(jack_client_t* c, const std::string& port, double seconds) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (std::chrono::steady_clock::now() < end) {
    if (jack_port_by_name(c, port.c_str())) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return false;
}

// The player's ports exist from their registration, before its client is active, and JACK
// refuses to connect an inactive client's ports: tried again until it accepts (or 30 s).
bool connect(jack_client_t* c, const std::string& from, const std::string& to) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (std::chrono::steady_clock::now() < end) {
    const int r = jack_connect(c, from.c_str(), to.c_str());
    if (r == 0 || r == EEXIST) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  std::fprintf(stderr, "jack_record: cannot connect %s to %s\n", from.c_str(), to.c_str());
  return false;
}

Event parse_event(const char* s, unsigned char status) {
  unsigned long long frame = 0;
  unsigned a = 0, b = 0;
  if (std::sscanf(s, "%llu:%u:%u", &frame, &a, &b) != 3) {
    std::fprintf(stderr, "jack_record: bad event '%s' (FRAME:A:B)\n", s);
    std::exit(2);
  }
  return {frame, {status, static_cast<unsigned char>(a), static_cast<unsigned char>(b)}};
}

}  // namespace

int main(int argc, char** argv) {
  std::string from = "maille", out, midi_to;
  std::size_t channels = 1;
  Recorder r;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string k = argv[i];
    if (k == "--from")
      from = argv[i + 1];
    else if (k == "--channels")
      channels = std::stoul(argv[i + 1]);
    else if (k == "--frames")
      r.want = std::stoull(argv[i + 1]);
    else if (k == "--out")
      out = argv[i + 1];
    else if (k == "--midi-to")
      midi_to = argv[i + 1];
    else if (k == "--note")
      r.events.push_back(parse_event(argv[i + 1], 0x90));
    else if (k == "--cc")
      r.events.push_back(parse_event(argv[i + 1], 0xB0));
    else {
      std::fprintf(stderr, "jack_record: unknown option %s\n", k.c_str());
      return 2;
    }
  }
  jack_status_t status{};
  r.client = jack_client_open("maille_test_recorder", JackNoStartServer, &status);
  if (!r.client) {
    std::fprintf(stderr, "jack_record: no JACK server (status 0x%x)\n", unsigned(status));
    return 1;
  }
  for (std::size_t c = 0; c < channels; ++c) {
    r.in.push_back(jack_port_register(r.client, ("in_" + std::to_string(c + 1)).c_str(),
                                      JACK_DEFAULT_AUDIO_TYPE, JackPortIsInput, 0));
    r.data.emplace_back().reserve(r.want);
  }
  if (!midi_to.empty())
    r.midi = jack_port_register(r.client, "midi_out", JACK_DEFAULT_MIDI_TYPE, JackPortIsOutput, 0);
  jack_set_process_callback(r.client, process, &r);
  jack_set_freewheel_callback(r.client, on_freewheel, &r);
  if (jack_activate(r.client)) return 1;
  for (std::size_t c = 0; c < channels; ++c) {
    const std::string port = from + ":out_" + std::to_string(c + 1);
    if (!wait_for(r.client, port, 30)) {
      std::fprintf(stderr, "jack_record: no port %s after 30 s\n", port.c_str());
      return 1;
    }
    if (!connect(r.client, port, jack_port_name(r.in[c]))) return 1;
  }
  if (r.midi) {
    if (!wait_for(r.client, midi_to, 30)) {
      std::fprintf(stderr, "jack_record: no MIDI port %s after 30 s\n", midi_to.c_str());
      return 1;
    }
    if (!connect(r.client, jack_port_name(r.midi), midi_to)) return 1;
  }
  jack_set_freewheel(r.client, 1);
  // Until FRAMES, or the player's ports are gone, or nothing came for 20 s (the graph stalled:
  // said, and a failure, rather than a silent short recording).
  auto last = std::chrono::steady_clock::now();
  std::uint64_t seen = 0;
  bool stalled = false;
  while (r.got.load() < r.want) {
    if (!jack_port_by_name(r.client, (from + ":out_1").c_str())) break;  // the player ended
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    const auto now = std::chrono::steady_clock::now();
    if (r.got.load() != seen) seen = r.got.load(), last = now;
    if (now - last > std::chrono::seconds(20)) {
      stalled = true;
      break;
    }
  }
  jack_set_freewheel(r.client, 0);
  const jack_nframes_t period = jack_get_buffer_size(r.client);
  const int rate = int(jack_get_sample_rate(r.client));
  jack_deactivate(r.client);
  jack_client_close(r.client);
  const std::uint64_t got = r.got.load();
  for (auto& d : r.data) d.resize(got);
  maille::write_wav(out, r.data, rate, maille::audio::SampleFormat::float32,
                    std::vector<double>(channels, 1.0));
  std::printf("recorded %llu frames, period %u\n", static_cast<unsigned long long>(got), period);
  for (const Event& e : r.events)
    std::printf("midi at frame %llu%s\n", static_cast<unsigned long long>(e.frame),
                e.sent ? "" : " (NOT SENT)");
  if (stalled)
    std::fprintf(stderr, "jack_record: the graph stalled in freewheel after %llu frames\n",
                 static_cast<unsigned long long>(got));
  return got > 0 && !stalled ? 0 : 1;
}
