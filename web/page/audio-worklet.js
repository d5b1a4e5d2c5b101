// The listened channels ([[listen]]) played as they are simulated. The engine makes the samples
// as `maille run --audio` does, at the scene's [audio] rate (the Playground's listen stage:
// exact every K steps, else the engine's sinc or linear StreamResampler; docs/sound.md), and the
// page's AudioContext runs at that rate, so this node plays them one for one: no resampling
// here (the browser converts the context's rate to the device's, as any page's audio).
// Gain: 0.99 / the largest |sample| heard so far on the channel (the command line's automatic
// gain takes the whole run's peak, which a live page cannot know). Channel 0 goes left, channel 1
// (or 0 again) right. When the simulation runs slower than real time the buffer runs dry and the
// output is silent until more arrives; it never holds more than half a second.
class MailleListen extends AudioWorkletProcessor {
  constructor() {
    super();
    this.buf = new Float32Array(0);  // interleaved frames not played yet
    this.channels = 1;
    this.pos = 0;                    // next frame of buf to play
    this.peak = [1e-12, 1e-12];
    this.port.onmessage = (e) => {
      const { samples, channels } = e.data;
      if (channels !== this.channels) { this.buf = new Float32Array(0); this.pos = 0; }
      this.channels = channels;
      for (let i = 0; i < samples.length; ++i) {
        const c = i % channels;
        if (c < 2) this.peak[c] = Math.max(this.peak[c], Math.abs(samples[i]));
      }
      const rest = this.buf.subarray(this.pos * channels);
      const merged = new Float32Array(rest.length + samples.length);
      merged.set(rest); merged.set(samples, rest.length);
      this.pos = 0;
      const maxFrames = Math.ceil(sampleRate / 2);
      const frames = merged.length / channels;
      this.buf = frames > maxFrames ? merged.subarray((frames - maxFrames) * channels) : merged;
    };
  }
  process(inputs, outputs) {
    const out = outputs[0], n = out[0].length, ch = this.channels;
    const frames = this.buf.length / ch;
    for (let i = 0; i < n; ++i) {
      const have = this.pos < frames;
      for (let c = 0; c < out.length; ++c) {
        const k = Math.min(c, ch - 1);
        out[c][i] = have ? 0.99 * this.buf[this.pos * ch + k] / this.peak[Math.min(k, 1)] : 0;
      }
      if (have) this.pos += 1;
    }
    return true;
  }
}
registerProcessor('maille-listen', MailleListen);
