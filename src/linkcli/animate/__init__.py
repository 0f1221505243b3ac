"""`--animate FILE.gif|FILE.mp4|FILE.svg`: a solved problem's linkage moving over its motion.

`scene` gathers what moves, from any mechanism's Skeleton (mechanisms.protocol) or a
problem type's own drawing (`types/<type>/animation.py`); `figure` draws it in the still
plots' style (matplotlib); `raster` writes GIF (Pillow) and MP4 (imageio-ffmpeg); `smil`
writes a self-contained SVG that plays with SMIL (no script). Heavy imports stay inside
the functions that use them.
"""
