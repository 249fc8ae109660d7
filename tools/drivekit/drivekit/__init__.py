"""drivekit: the drive's host tools as one package (today drive-campaign:
campaign.py, campaign_spec.py, campaign_worker.py, campaign_report.py)."""
