"""The workflow's side of a run: its description (run_spec), capsim's command line
(command_line), the job that runs or resumes one segment of it (job), and the results
archive that keeps it (archive)."""
