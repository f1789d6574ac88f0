"""Roads from GPS tracks and maps: ``truckmpc road import gpx|csv``, ``road info``, ``road plot``,
and the noise study.

Reading a track into a road is :mod:`truckmpc.roads`'s (:mod:`~truckmpc.roads.gpx`,
:mod:`~truckmpc.roads.latlon` and :mod:`~truckmpc.roads.gps`: ``load_road`` reads a ``.gpx``
too); this package sits above it and above the simulation. Modules: :mod:`~truckmpc.geo.files`
(imported road files), :mod:`~truckmpc.geo.info` (``road info`` figures),
:mod:`~truckmpc.geo.synthetic` (noisy tracks with known truth), :mod:`~truckmpc.geo.study` (the
noise study), :mod:`~truckmpc.geo.options` (the import's defaults) and :mod:`~truckmpc.geo.commands`
(what the road commands of :mod:`truckmpc.cli.road` call).

Nothing is imported here, so that the CLI can load its options without scipy, pyproj or gpxpy.
"""
