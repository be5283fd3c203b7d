W=/work/wt-audio-detect
g++ -std=c++20 -O2 -I$W/audio/include -I$W/core/include -I$W/audio/src dbg.cc $W/build/audio/libbouncecal_audio.a $W/build/core/libbouncecal_core.a -lsndfile -lfftw3f -o dbg
