// The listened channels ([[listen]]) played as they are simulated: samples arrive at the step
// rate (one per step and channel, interleaved), are resampled linearly to the context's rate
// and scaled by an automatic gain (0.9 / the largest |sample| heard so far, per channel).
// Channel 0 goes left, channel 1 (or 0 again) right. When the simulation runs slower than real
// time the buffer runs dry and the output is silent until more arrives; it never holds more than
// half a second.
class MailleListen extends AudioWorkletProcessor {
  constructor() {
    super();
    this.buf = new Float32Array(0);  // interleaved frames not played yet
    this.channels = 1;
    this.stepRate = 1;
    this.pos = 0;                    // read position in frames within buf
    this.peak = [1e-12, 1e-12];
    this.port.onmessage = (e) => {
      const { samples, channels, stepRate } = e.data;
      if (channels !== this.channels) { this.buf = new Float32Array(0); this.pos = 0; }
      this.channels = channels; this.stepRate = stepRate;
      for (let i = 0; i < samples.length; ++i) {
        const c = i % channels;
        if (c < 2) this.peak[c] = Math.max(this.peak[c], Math.abs(samples[i]));
      }
      const keep = Math.floor(this.pos) * channels;
      const rest = this.buf.subarray(keep);
      const merged = new Float32Array(rest.length + samples.length);
      merged.set(rest); merged.set(samples, rest.length);
      this.pos -= Math.floor(this.pos);
      const maxFrames = Math.ceil(stepRate / 2);
      const frames = merged.length / channels;
      this.buf = frames > maxFrames ? merged.subarray((frames - maxFrames) * channels) : merged;
    };
  }
  process(inputs, outputs) {
    const out = outputs[0], n = out[0].length, ch = this.channels;
    const frames = this.buf.length / ch, advance = this.stepRate / sampleRate;
    for (let i = 0; i < n; ++i) {
      const j = Math.floor(this.pos), f = this.pos - j;
      const have = j + 1 < frames;
      for (let c = 0; c < out.length; ++c) {
        const k = Math.min(c, ch - 1);
        out[c][i] = have ? 0.9 * (this.buf[j * ch + k] * (1 - f) + this.buf[(j + 1) * ch + k] * f) /
                               this.peak[Math.min(k, 1)] : 0;
      }
      if (have) this.pos += advance;
    }
    return true;
  }
}
registerProcessor('maille-listen', MailleListen);
