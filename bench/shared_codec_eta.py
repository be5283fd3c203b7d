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

Usage: shared_codec_eta.py BOUNCECAL [--recordings DIR] [--cache DIR] [--json OUT]
                          [--settings issue|rates]
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


def eta_bar(binary, path):
    run = subprocess.run([binary, "analyze", str(path), "--json", "-"], capture_output=True,
                         text=True)
    if run.returncode != 0:
        return None
    try:
        sequences = json.loads(run.stdout)["recordings"][0]["sequences"]
    except (ValueError, KeyError, IndexError):
        return None
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
    parser.add_argument("--settings", choices=["issue", "rates"], default="issue",
                        help="issue: the 4 codecs of issue 30; rates: 14 rates and bit rates")
    args = parser.parse_args()
    cache = pathlib.Path(args.cache)
    cache.mkdir(parents=True, exist_ok=True)
    wavs = sorted(pathlib.Path(args.recordings).rglob("*.wav"))
    rows = []
    for wav in wavs:
        reference = eta_bar(args.binary, wav)
        for name, (ext, options) in (RATES if args.settings == "rates" else CODECS).items():
            copy = cache / f"{wav.parent.name}_{wav.stem}_{name}.{ext}"
            if not copy.exists():
                subprocess.run(["ffmpeg", "-nostdin", "-loglevel", "error", "-y", "-i", str(wav)] +
                               options + [str(copy)], check=True)
            encoded = eta_bar(args.binary, copy)
            row = {"recording": f"{wav.parent.name}/{wav.name}", "codec": name}
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
    if args.json:
        pathlib.Path(args.json).write_text(json.dumps(rows, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
