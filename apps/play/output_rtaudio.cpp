// The RtAudio drivers (`--driver alsa|pulse`; audio_output.hpp): RtAudio's ALSA or PulseAudio
// API, float32 interleaved; RtAudio's callback calls the AudioCallback. Underflows RtAudio
// reports are counted as xruns.
#include <algorithm>

#include "audio_output.hpp"

#ifdef MAILLE_WITH_RTAUDIO
#include <rtaudio/RtAudio.h>

#include <string>

namespace maille::play {

namespace {

class RtOutput final : public AudioOutput {
 public:
  explicit RtOutput(RtAudio::Api api) : api_(api) {}
  ~RtOutput() override { stop(); }

  bool start(const OutputRequest& r, const CallbackFactory& make_callback, std::string& why) {
    try {
      audio_ = std::make_unique<RtAudio>(api_);
      audio_->showWarnings(false);
      const unsigned count = audio_->getDeviceCount();
      if (count == 0) {
        why = "no output device";
        return false;
      }
      RtAudio::StreamParameters out;
      out.deviceId = audio_->getDefaultOutputDevice();
      if (!r.device.empty()) {
        bool found = false;
        for (unsigned d = 0; d < count && !found; ++d) {
          const RtAudio::DeviceInfo info = audio_->getDeviceInfo(d);
          if (info.probed && info.name.find(r.device) != std::string::npos)
            out.deviceId = d, found = true;
        }
        if (!found) {
          why = "no device named like '" + r.device + "'";
          return false;
        }
      }
      device_ = audio_->getDeviceInfo(out.deviceId).name;
      out.nChannels = static_cast<unsigned>(r.channels);
      unsigned frames = static_cast<unsigned>(r.buffer);
      RtAudio::StreamOptions options;
      options.flags = RTAUDIO_MINIMIZE_LATENCY | RTAUDIO_SCHEDULE_REALTIME;
      options.streamName = r.client;
      rate_ = r.rate;
      // The callback is made for the period RtAudio settled on while opening (`frames`); a
      // larger period handed later is split by the callback itself.
      audio_->openStream(&out, nullptr, RTAUDIO_FLOAT32, static_cast<unsigned>(r.rate), &frames,
                         &RtOutput::process, this, &options);
      buffer_ = frames;
      callback_ = make_callback(rate_, buffer_);
      if (!callback_) {
        why = "the model cannot play at " + std::to_string(rate_) + " Hz";
        return false;
      }
      audio_->startStream();
      latency_ = audio_->getStreamLatency();
      return true;
    } catch (const RtAudioError& e) {
      why = e.getMessage();
      return false;
    }
  }

  std::string describe() const override {
    return RtAudio::getApiDisplayName(api_) + " through RtAudio (device '" + device_ + "')";
  }
  double latency_seconds() const override { return double(buffer_ + latency_) / double(rate_); }
  int rate() const override { return rate_; }
  std::size_t buffer() const override { return buffer_; }
  bool is_jack() const override { return false; }
  void stop() override {
    if (!audio_) return;
    try {
      if (audio_->isStreamRunning()) audio_->stopStream();
      if (audio_->isStreamOpen()) audio_->closeStream();
    } catch (const RtAudioError&) {
    }
    audio_.reset();
  }

 private:
  static int process(void* out, void*, unsigned frames, double, RtAudioStreamStatus status,
                     void* self) {
    auto* me = static_cast<RtOutput*>(self);
    if (!me->callback_) return 0;
    if (status & RTAUDIO_OUTPUT_UNDERFLOW) me->callback_->xrun();
    me->callback_->process_interleaved(static_cast<float*>(out), frames);
    return 0;
  }

  RtAudio::Api api_;
  std::unique_ptr<RtAudio> audio_;
  AudioCallback* callback_ = nullptr;
  int rate_ = 0;
  std::size_t buffer_ = 0;
  long latency_ = 0;
  std::string device_;
};

}  // namespace

std::unique_ptr<AudioOutput> open_rtaudio(const OutputRequest& r,
                                          const CallbackFactory& make_callback, std::string& why) {
  const RtAudio::Api api = r.driver == "alsa" ? RtAudio::LINUX_ALSA : RtAudio::LINUX_PULSE;
  std::vector<RtAudio::Api> compiled;
  RtAudio::getCompiledApi(compiled);
  if (std::find(compiled.begin(), compiled.end(), api) == compiled.end()) {
    why = "this RtAudio was built without it";
    return nullptr;
  }
  return started(std::make_unique<RtOutput>(api), r, make_callback, why);
}
}  // namespace maille::play

#endif  // MAILLE_WITH_RTAUDIO
