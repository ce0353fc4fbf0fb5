/* Helpers shared by the output tests: temporary directories and directory listings. */
#ifndef VBL_OUTPUT_TEST_UTIL_H
#define VBL_OUTPUT_TEST_UTIL_H

/* mkdtemp("/tmp/vbl-output-XXXXXX"); aborts the test on failure. Returned string is static per call slot. */
char* out_make_temp_dir(void);
/* Removes every file in `dir` and the directory. */
void out_remove_dir(const char* dir);
/* Number of entries in `dir` (excluding . and ..); `first` gets the first name if not NULL. */
int out_count_entries(const char* dir, char* first, int first_size);
/* Joins dir and name into a static rotating buffer. */
const char* out_path(const char* dir, const char* name);
/* Runs a shell command, captures stdout+stderr (malloc'd, caller frees) and returns the exit status. */
int out_run(const char* command, char** output);

#endif
