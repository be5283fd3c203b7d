#!/usr/bin/env python3
"""eta-bar of lossy copies of real recordings against the WAV's, with stated sigmas.

Encodes every WAV under a recordings directory (default /work/shared/recordings) at AAC 128k,
Opus 64k, MP3 128k and Vorbis q4 with ffmpeg (cached in --cache), runs `bouncecal analyze` on the
WAV and each copy, and prints per copy the first sequence's eta-bar, |difference| to the WAV's
and that difference over the combined stated sigma. The counts within 0.002 / 0.003 and beyond
2 / 3 combined sigmas are the issue 30 figures (docs/codecs.md).

On main, 2026-11-28, the shared folder's 12 recordings x 4 settings: 44 copies with an eta-bar,
30 within 0.002, 33 within 0.003, 8 beyond 2 and 6 beyond 3 combined sigmas (among them
zaky-ptv ping-pong Opus and MP3, 34-40 sigma: another sequence; basketball MP3), 2 with none;
the same counts before and after the response timing's disagreement rule (docs/detector.md).

`--settings formats` writes lossless copies instead (32-bit float, 24-bit, 44.1 and 48 kHz
resampled as 16-bit and as float, 6 dB quieter, FLAC): the same samples as a DAW or a converter
exports them, whose answers should be the WAV's. With `--onsets` every first-sequence member is
also matched to the WAV's (within 20 ms) and listed where the two differ by more than 3 combined
stated sigmas and 0.3 ms: a confident onset that the file's format alone moved. 2026-12-06, the
shared recordings (88 copies) and the detector suite (160; 8 without an eta-bar, as their WAVs):
before `TakeLouderRestsAsImpacts` ran in every file (docs/detector.md) 86 and 152 within 0.002
(Palla-audio's two 48 kHz copies 3+ combined sigmas off: they timed its 3rd bounce, the WAV a
faint sound 8.4 ms before it) and 13 of 4354 members moved; after, 88 and 152, and 9 (eeps
ping-pong and fr4nci Audio at 48 kHz 0.3-0.7 ms at +-0.01-0.14 ms; rimbalzi's 10th bounce at
48 kHz on a faint sound 4.6 ms before it, 13 dB under its rest; ub-mth337 ping-pong's last
bounce, another sound 20 ms on). The coverage suite (320 copies, after): 291 of 293 with an
eta-bar within 0.002, 2 of 1943 members moved: copper_e065_j3_s3113 at 44.1 kHz (16-bit and
float) moved its 2nd bounce onto a noise sound 19.8 dB under it and 6 ms before it, which the
sequence's neighbour test took as fitting the ratios of this 3 %-scatter ball better
(merged_alternatives.h; 0.5922 +- 0.00036 against the WAV's 0.5981, 12 sigmas); lead s4101 at
-6 dB and s4112 at 44.1 kHz refuse. Since a member with reference ratios on one side weighs only
sounds within a rise threshold of it (2026-12-06, stop 67): 293 of 293, 0 members moved.

`--settings impairments` (stop 67, 9 settings, final code): the shared recordings' 99 copies 93
within 0.002, 5 beyond 2 and 2 beyond 3 combined sigmas, 2 without an eta-bar, 41 of 2699
members moved. The two beyond 3 are zaky-ptv's start: through the 3 kHz low-pass its chain
starts at the file's loudest sound (0.045 s), which the WAV leaves out (there it rose 9.1 dB in a
band, under the threshold, 34 ms after another sound, and a residual-only sound is never tracked
back to), 0.2632 +- 0.00044 against 0.2527 +- 0.00065; trimmed by 333 samples its first bounce
rose 9.25 dB instead of 11.38 (where the 0.25 ms frames fall on a click moves a band's rise by up
to 2.5 dB: 8.9-11.4 dB as the file is trimmed by 0-11 samples), was residual-only, and the chain
started at the 2nd bounce, 0.2419 +- 0.00095; trimmed by 3 samples the file's first sequence was
a chain of late sounds, by 8 it had none. This ball's e rises as it slows, so the first three
flights' eta-bar moves 0.01 with the start (docs/codecs.md has what was tried). Beyond 2:
Palla-audio with noise (2.9) and trimmed (2.5), zaky-ptv 12 dB louder and clipped (2.8). Before
the clipping rules (onset_locator.cc, clipped_span.h) handling_thumps of the detector suite 20 dB
louder read 7.8 and eeps ping-pong 20 dB louder 3.3 combined sigmas off. The detector suite's
180 copies: 169 within 0.002, none beyond 2 sigmas, 11 without (9 as their WAVs); the coverage
suite's 360: 303 within 0.002, none beyond 2 sigmas, 52 without (27 as their WAVs; the others
lead drops of 3-5 bounces with the padding, low-pass, echo, noise or trim).

Usage: shared_codec_eta.py BOUNCECAL [--recordings DIR] [--cache DIR] [--json OUT]
                          [--settings issue|rates|formats|impairments] [--onsets]
"""
import argparse
import json
import math
import pathlib
import subprocess
import sys

CODECS = {
    "aac128k": ("m4a", ["-c:a", "aac", "-b:a", "128k"]),
    "opus64k": ("opus", ["-c:a", "libopus", "-b:a", "64k"]),
    "mp3128k": ("mp3", ["-c:a", "libmp3lame", "-b:a", "128k"]),
    "vorbisq4": ("ogg", ["-c:a", "libvorbis", "-q:a", "4"]),
}

# `--settings rates`: telephone and phone rates and other bit rates (docs/codecs.md, "The
# detector suite at telephone and phone rates"; 14 settings, 280 copies of the detector suite).
RATES = {
    "16k": ("wav", ["-ar", "16000", "-c:a", "pcm_s16le"]),
    "8k": ("wav", ["-ar", "8000", "-c:a", "pcm_s16le"]),
    "8k_ulaw": ("wav", ["-ar", "8000", "-c:a", "pcm_mulaw"]),
    "aac16k": ("m4a", ["-ar", "16000", "-c:a", "aac", "-b:a", "64k"]),
    "opus16k": ("opus", ["-ar", "16000", "-c:a", "libopus", "-b:a", "32k"]),
    "mp3_16k": ("mp3", ["-ar", "16000", "-c:a", "libmp3lame", "-b:a", "64k"]),
    "vorbis16k": ("ogg", ["-ar", "16000", "-c:a", "libvorbis", "-q:a", "4"]),
    "aac22k": ("m4a", ["-ar", "22050", "-c:a", "aac", "-b:a", "64k"]),
    "mp3_44k64": ("mp3", ["-ar", "44100", "-c:a", "libmp3lame", "-b:a", "64k"]),
    "aac96k": ("m4a", ["-c:a", "aac", "-b:a", "96k"]),
    "opus48k": ("opus", ["-c:a", "libopus", "-b:a", "48k"]),
    "mp3_96k": ("mp3", ["-c:a", "libmp3lame", "-b:a", "96k"]),
    "vorbisq2": ("ogg", ["-c:a", "libvorbis", "-q:a", "2"]),
    "aac44k128": ("m4a", ["-ar", "44100", "-c:a", "aac", "-b:a", "128k"]),
}

# `--settings formats`: lossless exports of the same recording.
FORMATS = {
    "float": ("wav", ["-c:a", "pcm_f32le"]),
    "s24": ("wav", ["-c:a", "pcm_s24le"]),
    "44k1": ("wav", ["-ar", "44100", "-c:a", "pcm_s16le"]),
    "48k": ("wav", ["-ar", "48000", "-c:a", "pcm_s16le"]),
    "44k1_float": ("wav", ["-ar", "44100", "-c:a", "pcm_f32le"]),
    "48k_float": ("wav", ["-ar", "48000", "-c:a", "pcm_f32le"]),
    "minus6db": ("wav", ["-af", "volume=-6dB", "-c:a", "pcm_s16le"]),
    "flac": ("flac", ["-c:a", "flac"]),
}

# `--settings impairments`: what a room, a phone's microphone chain or a careless export adds to
# the same recording (16-bit WAVs at the recording's rate): 100 ms of silence before it, 12 and 20
# dB of gain clipped at full scale, a 300 Hz high-pass (a phone's wind filter), a 3 kHz low-pass,
# an echo 17 ms after every sound at 0.3 of its level, white noise at -50 dBFS, a DC offset, the
# first 333 samples cut. The drop is the same, so a copy whose eta-bar is beyond 3 combined sigmas
# of the WAV's is a confident wrong answer. {rate} and {layout} are the recording's own.
PCM = ["-c:a", "pcm_s16le"]
IMPAIRMENTS = {
    "pad100ms": ("wav", ["-af", "adelay=delays=100:all=1"] + PCM),
    "plus12db": ("wav", ["-af", "volume=12dB"] + PCM),
    "highpass": ("wav", ["-af", "highpass=f=300"] + PCM),
    "lowpass3k": ("wav", ["-af", "lowpass=f=3000"] + PCM),
    "echo17ms": ("wav", ["-af", "aecho=1:1:17:0.3"] + PCM),
    "noise50": ("wav", ["-filter_complex",
                        "anoisesrc=r={rate}:a=0.00316:c=white:seed=7,"
                        "aformat=channel_layouts={layout}[n];"
                        "[0:a][n]amix=inputs=2:duration=first:normalize=0"] + PCM),
    "dc": ("wav", ["-af", "dcshift=0.02"] + PCM),
    "trim333": ("wav", ["-af", "atrim=start_sample=333"] + PCM),
    "plus20db": ("wav", ["-af", "volume=20dB"] + PCM),
}
# Where a setting moves the recording in time, by how much: seconds, or samples at its rate.
SHIFT_S = {"pad100ms": 0.1}
SHIFT_SAMPLES = {"trim333": -333}

SETTINGS = {"issue": CODECS, "rates": RATES, "formats": FORMATS, "impairments": IMPAIRMENTS}


def stream_format(path):
    """{rate} and {layout} of the file's audio stream, for the settings that name them."""
    run = subprocess.run(["ffprobe", "-v", "error", "-select_streams", "a:0", "-show_entries",
                          "stream=sample_rate,channels", "-of", "json", str(path)],
                         capture_output=True, text=True, check=True)
    stream = json.loads(run.stdout)["streams"][0]
    channels = int(stream["channels"])
    layout = {1: "mono", 2: "stereo"}.get(channels, f"{channels}c")
    return {"rate": stream["sample_rate"], "layout": layout}


def analysis(binary, path):
    run = subprocess.run([binary, "analyze", str(path), "--json", "-"], capture_output=True,
                         text=True)
    if run.returncode != 0:
        return None
    try:
        return json.loads(run.stdout)["recordings"][0]
    except (ValueError, KeyError, IndexError):
        return None


def members(recording):
    """(onset, sigma) of the first sequence's members."""
    if not recording:
        return []
    return [(i["onset_s"], i["onset_uncertainty_s"]) for i in recording["impacts"]
            if i.get("sequence") == 0]


def moved_members(reference, copy, shift_s=0.0):
    """The copy's members more than 3 combined sigmas and 0.3 ms from the WAV's nearest."""
    moved = []
    for onset, sigma in copy:
        onset -= shift_s
        near = [m for m in reference if abs(m[0] - onset) < 0.02]
        if not near:
            continue
        wav_onset, wav_sigma = min(near, key=lambda m: abs(m[0] - onset))
        distance = abs(onset - wav_onset)
        if distance > max(3 * math.hypot(sigma, wav_sigma), 3e-4):
            moved.append((onset, wav_onset, sigma, wav_sigma))
    return moved


def eta_bar_of(recording):
    if not recording:
        return None
    sequences = recording["sequences"]
    if not sequences or sequences[0].get("energy_loss_mean_first_n") is None:
        return None
    s = sequences[0]
    return s["energy_loss_mean_first_n"], s["energy_loss_mean_first_n_uncertainty"]


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("binary")
    parser.add_argument("--recordings", default="/work/shared/recordings")
    parser.add_argument("--cache", default="/tmp/shared_codec_eta")
    parser.add_argument("--json")
    parser.add_argument("--settings", choices=sorted(SETTINGS), default="issue",
                        help="issue: the 4 codecs of issue 30; rates: 14 rates and bit rates; "
                        "formats: 8 lossless exports; impairments: 9 rooms, filters and "
                        "exports")
    parser.add_argument("--onsets", action="store_true",
                        help="also list sequence members a copy moved beyond 3 sigmas")
    args = parser.parse_args()
    cache = pathlib.Path(args.cache)
    cache.mkdir(parents=True, exist_ok=True)
    wavs = sorted(pathlib.Path(args.recordings).rglob("*.wav"))
    rows = []
    compared = moved = 0
    for wav in wavs:
        wav_analysis = analysis(args.binary, wav)
        reference = eta_bar_of(wav_analysis)
        for name, (ext, options) in SETTINGS[args.settings].items():
            copy = cache / f"{wav.parent.name}_{wav.stem}_{name}.{ext}"
            if not copy.exists():
                if any("{" in option for option in options):
                    fields = stream_format(wav)
                    options = [option.format(**fields) for option in options]
                subprocess.run(["ffmpeg", "-nostdin", "-loglevel", "error", "-y", "-i", str(wav)] +
                               options + [str(copy)], check=True)
            copy_analysis = analysis(args.binary, copy)
            encoded = eta_bar_of(copy_analysis)
            row = {"recording": f"{wav.parent.name}/{wav.name}", "codec": name}
            if args.onsets:
                copy_members = members(copy_analysis)
                compared += len(copy_members)
                shift_s = SHIFT_S.get(name, 0.0)
                if name in SHIFT_SAMPLES and copy_analysis:
                    shift_s = SHIFT_SAMPLES[name] / copy_analysis["sample_rate_hz"]
                for onset, wav_onset, sigma, wav_sigma in moved_members(
                        members(wav_analysis), copy_members, shift_s):
                    moved += 1
                    print(f"  moved: {row['recording']} {name} {onset:.5f} s against the WAV's "
                          f"{wav_onset:.5f} s, stated +-{sigma * 1e3:.2f} / +-{wav_sigma * 1e3:.2f} ms",
                          flush=True)
            if reference and encoded:
                diff = abs(encoded[0] - reference[0])
                sigma = math.hypot(encoded[1], reference[1])
                row.update(wav=reference[0], wav_sigma=reference[1], copy=encoded[0],
                           copy_sigma=encoded[1], diff=diff,
                           sigmas=diff / sigma if sigma > 0 else math.inf)
            elif not reference:
                # Not a loss of the codec's: the WAV gives none either.
                row["wav_has_none"] = True
            rows.append(row)
            if "diff" in row:
                text = (f"wav {row['wav']:.4f}+-{row['wav_sigma']:.5f} copy {row['copy']:.4f}"
                        f"+-{row['copy_sigma']:.5f} |d| {row['diff']:.4f} {row['sigmas']:.2f} sig")
            elif row.get("wav_has_none"):
                text = "no eta-bar (nor has the WAV)"
            else:
                text = "no eta-bar"
            print(f"{row['recording']:40s} {name:9s} {text}", flush=True)
    done = [r for r in rows if "diff" in r]
    print(f"copies {len(rows)}: within 0.002 {sum(r['diff'] <= 0.002 for r in done)}, "
          f"within 0.003 {sum(r['diff'] <= 0.003 for r in done)}, "
          f"within 0.005 {sum(r['diff'] <= 0.005 for r in done)}, "
          f"beyond 2 sigma {sum(r['sigmas'] > 2 for r in done)}, "
          f"beyond 3 sigma {sum(r['sigmas'] > 3 for r in done)}, "
          f"no eta-bar {len(rows) - len(done)} "
          f"(the WAV has none either: {sum(bool(r.get('wav_has_none')) for r in rows)})")
    if args.onsets:
        print(f"members {compared}: beyond 3 combined sigmas and 0.3 ms of the WAV's {moved}")
    if args.json:
        pathlib.Path(args.json).write_text(json.dumps(rows, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
