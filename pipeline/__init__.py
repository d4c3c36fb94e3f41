"""The workflow's side of a run: its description (run_spec), the job that runs or resumes
one segment of it (job), and the results archive that keeps it (archive)."""
