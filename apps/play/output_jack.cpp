// The JACK driver (`--driver jack`; audio_output.hpp): a JACK client of its own (libjack
// directly: its ports, its latency and its xrun count are JACK's own), one output port per
// channel, out_1, out_2, ..., connected to the server's physical playback ports when there are
// any. JACK's process callback calls the AudioCallback: in `maille play` the model is computed
// there (no ring, no extra latency; in freewheel mode the graph waits for it, which the tests
// use); in the viewer it copies from the physics thread's ring.
#include "audio_output.hpp"

#ifdef MAILLE_WITH_JACK
#include <jack/jack.h>
#include <pthread.h>

#include <cstdlib>
#include <string>
#include <vector>

namespace maille::play {

namespace {

class JackOutput final : public AudioOutput {
 public:
  ~JackOutput() override { stop(); }

  bool start(const OutputRequest& r, const CallbackFactory& make_callback, std::string& why) {
    jack_status_t status{};
    // JackNoStartServer: playing never starts a server behind the user's back (nor hangs
    // trying); a server is started by the user (qjackctl, jackd, PipeWire's JACK).
    client_ = jack_client_open(r.client.c_str(), JackNoStartServer, &status);
    if (!client_) {
      const char* server = std::getenv("JACK_DEFAULT_SERVER");
      why = std::string("no JACK server running (server '") + (server ? server : "default") +
            "', status 0x" + hex(unsigned(status)) + ")";
      return false;
    }
    rate_ = int(jack_get_sample_rate(client_));
    buffer_ = jack_get_buffer_size(client_);
    if (r.rate && rate_ != r.rate)
      note_ = "the JACK server runs at " + std::to_string(rate_) + " Hz (asked " +
              std::to_string(r.rate) + "): playing at the server's rate";
    callback_ = make_callback(rate_, buffer_);
    if (!callback_) {
      why = "the model cannot play at " + std::to_string(rate_) + " Hz";
      return false;
    }
    for (std::size_t c = 0; c < r.channels; ++c) {
      const std::string name = "out_" + std::to_string(c + 1);
      jack_port_t* p =
          jack_port_register(client_, name.c_str(), JACK_DEFAULT_AUDIO_TYPE, JackPortIsOutput, 0);
      if (!p) {
        why = "cannot register the JACK port " + name;
        return false;
      }
      ports_.push_back(p);
    }
    buffers_.assign(ports_.size(), nullptr);
    jack_set_process_callback(client_, &JackOutput::process, this);
    jack_set_xrun_callback(client_, &JackOutput::xrun, this);
    if (jack_activate(client_)) {
      why = "cannot activate the JACK client";
      return false;
    }
    active_ = true;
    connect_playback(r.device);
    name_ = jack_get_client_name(client_);
    return true;
  }

  std::string describe() const override {
    const char* server = std::getenv("JACK_DEFAULT_SERVER");
    return "JACK (server '" + std::string(server ? server : "default") + "', client '" + name_ +
           "', ports out_1.." + std::to_string(ports_.size()) + ")" +
           (note_.empty() ? "" : "; " + note_);
  }
  // One period plus the playback ports' latency, asked now: JACK recomputes it after
  // connections, asynchronously.
  double latency_seconds() const override {
    if (client_ && !ports_.empty()) {
      jack_latency_range_t range{};
      jack_port_get_latency_range(ports_[0], JackPlaybackLatency, &range);
      latency_frames_ = range.max;
    }
    return double(buffer_ + latency_frames_) / double(rate_);
  }
  int rate() const override { return rate_; }
  std::size_t buffer() const override { return buffer_; }
  bool is_jack() const override { return true; }
  void stop() override {
    if (!client_) return;
    if (active_) jack_deactivate(client_);
    jack_client_close(client_);
    client_ = nullptr;
    active_ = false;
  }

 private:
  static std::string hex(unsigned v) {
    static const char* digits = "0123456789abcdef";
    std::string s;
    do s.insert(s.begin(), digits[v & 15]), v >>= 4;
    while (v);
    return s;
  }

  // To the device's playback ports (`device`: a port name prefix, default "system:playback").
  void connect_playback(const std::string& device) {
    const char** physical =
        jack_get_ports(client_, device.empty() ? nullptr : device.c_str(), JACK_DEFAULT_AUDIO_TYPE,
                       JackPortIsInput | (device.empty() ? JackPortIsPhysical : 0));
    if (!physical) return;
    std::size_t n = 0;
    while (physical[n]) ++n;
    for (std::size_t c = 0; c < ports_.size() && n; ++c)
      jack_connect(client_, jack_port_name(ports_[c]), physical[c % n]);
    jack_free(physical);
  }

  // JACK's deactivation (stop()) cancels this thread asynchronously, wherever it is: inside the
  // model's step, the forced unwind met a frame that may not throw and std::terminate aborted
  // the program at Ctrl-C (cli.play_jack_osc, about one run in five; the core showed the cancel
  // inside the link loop). Cancellation is held off while the model runs, and a pending one is
  // taken when it is allowed again, here, outside the engine's frames.
  static int process(jack_nframes_t frames, void* self) {
    int cancel = PTHREAD_CANCEL_ENABLE;
    pthread_setcancelstate(PTHREAD_CANCEL_DISABLE, &cancel);
    auto* me = static_cast<JackOutput*>(self);
    for (std::size_t c = 0; c < me->ports_.size(); ++c)
      me->buffers_[c] = static_cast<float*>(jack_port_get_buffer(me->ports_[c], frames));
    me->callback_->process(me->buffers_.data(), frames);
    pthread_setcancelstate(cancel, nullptr);
    return 0;
  }
  static int xrun(void* self) {
    static_cast<JackOutput*>(self)->callback_->xrun();
    return 0;
  }

  jack_client_t* client_ = nullptr;
  bool active_ = false;
  std::vector<jack_port_t*> ports_;
  std::vector<float*> buffers_;
  AudioCallback* callback_ = nullptr;
  int rate_ = 0;
  std::size_t buffer_ = 0;
  mutable jack_nframes_t latency_frames_ = 0;
  std::string name_, note_;
};

}  // namespace

std::unique_ptr<AudioOutput> open_jack(const OutputRequest& r, const CallbackFactory& make_callback,
                                       std::string& why) {
  return started(std::make_unique<JackOutput>(), r, make_callback, why);
}
}  // namespace maille::play

#endif  // MAILLE_WITH_JACK
