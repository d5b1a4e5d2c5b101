// `maille play --driver alsa|pulse`: RtAudio's ALSA or PulseAudio API, float32 interleaved; the
// model is computed in RtAudio's callback. Underflows RtAudio reports are counted as xruns.
#include "play.hpp"

#ifdef MAILLE_WITH_RTAUDIO
#include <rtaudio/RtAudio.h>

#include <string>

namespace maille::app {

namespace {

class RtOutput final : public AudioOutput {
 public:
  explicit RtOutput(RtAudio::Api api) : api_(api) {}
  ~RtOutput() override { stop(); }

  bool start(const OutputRequest& r, const EngineFactory& make_engine, std::string& why) {
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
      // The engine needs the period: RtAudio may change `frames` while opening, so the engine
      // is made for the largest it could be given (a multiple of the asked size is enough).
      audio_->openStream(&out, nullptr, RTAUDIO_FLOAT32, static_cast<unsigned>(r.rate), &frames,
                         &RtOutput::process, this, &options);
      buffer_ = frames;
      engine_ = make_engine(rate_, buffer_);
      if (!engine_) {
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
    if (!me->engine_) return 0;
    if (status & RTAUDIO_OUTPUT_UNDERFLOW) me->engine_->xruns.fetch_add(1);
    float* o = static_cast<float*>(out);
    const std::size_t per = me->engine_->block.size() / me->engine_->channels;
    for (unsigned start = 0; start < frames;) {
      const unsigned n = static_cast<unsigned>(std::min<std::size_t>(frames - start, per));
      me->engine_->process_interleaved(o + std::size_t(start) * me->engine_->channels, n);
      start += n;
    }
    return 0;
  }

  RtAudio::Api api_;
  std::unique_ptr<RtAudio> audio_;
  PlayEngine* engine_ = nullptr;
  int rate_ = 0;
  std::size_t buffer_ = 0;
  long latency_ = 0;
  std::string device_;
};

}  // namespace

std::unique_ptr<AudioOutput> open_rtaudio(const OutputRequest& r, const EngineFactory& make_engine,
                                          std::string& why) {
  const RtAudio::Api api = r.driver == "alsa" ? RtAudio::LINUX_ALSA : RtAudio::LINUX_PULSE;
  std::vector<RtAudio::Api> compiled;
  RtAudio::getCompiledApi(compiled);
  if (std::find(compiled.begin(), compiled.end(), api) == compiled.end()) {
    why = "this RtAudio was built without it";
    return nullptr;
  }
  auto out = std::make_unique<RtOutput>(api);
  if (!out->start(r, make_engine, why)) return nullptr;
  return out;
}

}  // namespace maille::app

#else

namespace maille::app {

std::unique_ptr<AudioOutput> open_rtaudio(const OutputRequest&, const EngineFactory&,
                                          std::string& why) {
  why = "this maille was built without RtAudio (librtaudio-dev; scripts/setup.sh installs it)";
  return nullptr;
}

}  // namespace maille::app

#endif
