"""drivekit - the drive's SIL figures and the rule's checks, one module a
tool (tools/drivekit/README.md): metrics, sil_plot, sil_report, sweep,
sweep_maps, sweep_check, rule_check, campaign_check, est_grid,
motor_timeline, and drive-campaign's campaign, campaign_spec,
campaign_worker, campaign_report. Each has main(argv=None) returning its exit status: a
console script of pyproject.toml, or `python3 -m drivekit.MODULE` with
tools/drivekit on PYTHONPATH. Only sil_plot and sweep_maps (and sil_report
to draw) need matplotlib."""
