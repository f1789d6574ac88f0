"""Roads from GPS tracks and maps: ``truckmpc road import gpx|csv``, ``road info``, ``road plot``.

Modules: :mod:`~truckmpc.geo.gpx` (GPX reader), :mod:`~truckmpc.geo.latlon` (``lat,lon,ele``
tables), :mod:`~truckmpc.geo.track` (checks, jitter, geodesic distance), :mod:`~truckmpc.geo.smooth`
(elevation smoothing), :mod:`~truckmpc.geo.importer` (track to road), :mod:`~truckmpc.geo.files`
(imported road files), :mod:`~truckmpc.geo.info` (``road info`` figures),
:mod:`~truckmpc.geo.synthetic` (noisy tracks with known truth), :mod:`~truckmpc.geo.study` (the
noise study), :mod:`~truckmpc.geo.options` and :mod:`~truckmpc.geo.commands` (the CLI's part).

Nothing is imported here, so that the CLI can load its options without scipy, pyproj or gpxpy.
"""
