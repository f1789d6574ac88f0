"""Roads from GPS tracks and maps: ``truckmpc road import gpx|csv``, ``road info``, ``road plot``.

Modules: :mod:`~truckmpc.geo.gpx` (GPX reader), :mod:`~truckmpc.geo.latlon` (``lat,lon,ele``
tables), :mod:`~truckmpc.geo.track` (checks, jitter, geodesic distance), :mod:`~truckmpc.geo.smooth`
(elevation smoothing), :mod:`~truckmpc.geo.importer` (track to road), :mod:`~truckmpc.geo.files`
(imported road files), :mod:`~truckmpc.geo.info` (``road info`` figures),
:mod:`~truckmpc.geo.synthetic` (noisy tracks with known truth), :mod:`~truckmpc.geo.study` (the
noise study), :mod:`~truckmpc.geo.options` (the import's defaults) and :mod:`~truckmpc.geo.commands`
(what the road commands of :mod:`truckmpc.cli.road` call).

Nothing is imported here, so that the CLI can load its options without scipy, pyproj or gpxpy.
"""
