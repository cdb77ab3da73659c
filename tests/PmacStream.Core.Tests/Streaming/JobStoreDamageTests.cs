using PmacStream.Streaming;

namespace PmacStream.Core.Tests.Streaming;

/// <summary>
/// A damaged job database is found on open or on reading, named with the file and what is wrong, and kept aside
/// (never silently replaced or read as if it were sound).
/// </summary>
public class JobStoreDamageTests
{
    [Theory]
    [InlineData("cp_state", "'garbage'", "cp_state holds 'garbage', expected a session state")]
    [InlineData("cp_state", "'Running, Held'", "cp_state holds 'Running, Held'")]
    [InlineData("cp_time", "'yesterday'", "cp_time holds 'yesterday', expected a date and time")]
    [InlineData("strategy", "'warp'", "strategy holds 'warp', expected a strategy")]
    [InlineData("created", "'soon'", "created holds 'soon', expected a date and time")]
    [InlineData("cp_last_line", "NULL", "cp_last_line holds NULL, expected a whole number")]
    [InlineData("cp_last_line", "9223372036854775807", "cp_last_line holds 9223372036854775807, expected a whole number from 0 to 2147483647")]
    [InlineData("cp_chunk", "-3", "cp_chunk holds -3")]
    [InlineData("cp_next_line", "'next'", "cp_next_line holds 'next'")]
    [InlineData("cp_next_exact", "7", "cp_next_exact holds 7")]
    [InlineData("from_line", "0", "from_line holds 0")]
    [InlineData("line_probe", "'P501; #1J+'", "line_probe holds 'P501; #1J+'")]
    [InlineData("program_sha256", "x'00'", "program_sha256 holds 1 bytes of binary data")]
    public void Every_field_is_checked_and_a_bad_one_names_the_file_the_job_and_the_column(string column, string value, string expected)
    {
        var db = HostileJobDatabases.WithField(HostileJobDatabases.Folder("field"), column, value);
        using var store = JobStore.Open(db);

        var get = () => store.Get(1);
        var latest = () => store.LatestUnfinished();

        foreach (var read in new[] { get, latest })
        {
            var e = read.Should().Throw<JobStoreException>().Which;
            e.Problem.Should().Be(JobStoreProblem.BadRecord);
            e.Message.Should().StartWith($"{db}: job 1: ").And.Contain(expected).And.Contain("cannot be resumed");
        }
    }

    [Fact]
    public void A_sound_record_reads_back_as_written()
    {
        var db = HostileJobDatabases.Healthy(HostileJobDatabases.Folder("healthy"));
        using var store = JobStore.Open(db);
        store.Get(1)!.Checkpoint.Should().Be(HostileJobDatabases.Checkpoint);
    }

    [Fact]
    public void A_file_that_is_not_a_database_is_moved_aside_and_named()
    {
        var db = HostileJobDatabases.NotADatabase(HostileJobDatabases.Folder("notdb"));
        var bytes = File.ReadAllBytes(db);

        var e = FluentActions.Invoking(() => JobStore.Open(db)).Should().Throw<JobStoreException>().Which;

        e.Problem.Should().Be(JobStoreProblem.Damaged);
        e.Message.Should().StartWith($"{db}: the job database is damaged: it is not an SQLite database").And.Contain("moved aside to " + e.KeptAs);
        File.Exists(db).Should().BeFalse("the damaged file is moved, not left to be opened again");
        File.ReadAllBytes(e.KeptAs!).Should().Equal(bytes, "kept as it was, nothing deleted");
        using var fresh = JobStore.Open(db);
        fresh.List().Should().BeEmpty("the next open starts a new database beside the kept one");
    }

    [Fact]
    public void A_damaged_page_fails_the_integrity_check_and_is_kept_aside()
    {
        var db = HostileJobDatabases.PageDamaged(HostileJobDatabases.Folder("page"));

        var e = FluentActions.Invoking(() => JobStore.Open(db)).Should().Throw<JobStoreException>().Which;

        e.Problem.Should().Be(JobStoreProblem.Damaged);
        e.Message.Should().StartWith($"{db}: the job database is damaged: ");
        File.Exists(e.KeptAs).Should().BeTrue();
        File.Exists(db).Should().BeFalse();
    }

    [Fact]
    public void The_files_a_crash_leaves_open_as_they_are_with_the_job_and_its_last_checkpoint()
    {
        var db = HostileJobDatabases.CrashImage(HostileJobDatabases.Folder("crash"));
        File.Exists(db + "-wal").Should().BeTrue("the crash image holds the write-ahead log");

        using var store = JobStore.Open(db);
        store.LatestUnfinished()!.Checkpoint.Should().Be(HostileJobDatabases.Checkpoint);
    }

    [Fact]
    public void A_write_ahead_log_lost_after_a_crash_is_reported_not_read_as_no_job()
    {
        var db = HostileJobDatabases.WalMissing(HostileJobDatabases.Folder("walgone"));

        var e = FluentActions.Invoking(() => JobStore.Open(db)).Should().Throw<JobStoreException>().Which;

        e.Problem.Should().Be(JobStoreProblem.Damaged);
        e.Message.Should().Contain($"its write-ahead log {db}-wal is missing").And.Contain("did not close it").And.Contain("are lost");
        File.Exists(e.KeptAs).Should().BeTrue();
    }

    [Fact]
    public void A_damaged_write_ahead_log_is_reported_and_kept_with_its_database()
    {
        var db = HostileJobDatabases.WalDamaged(HostileJobDatabases.Folder("walbad"));
        var wal = File.ReadAllBytes(db + "-wal");

        var e = FluentActions.Invoking(() => JobStore.Open(db)).Should().Throw<JobStoreException>().Which;

        e.Problem.Should().Be(JobStoreProblem.Damaged);
        e.Message.Should().Contain($"frame 1 of its write-ahead log {db}-wal is damaged");
        File.ReadAllBytes(e.KeptAs + "-wal").Should().Equal(wal, "the log is kept beside its database");
        File.Exists(db + "-wal").Should().BeFalse();
    }

    [Fact]
    public void A_clean_close_leaves_nothing_that_looks_like_a_crash()
    {
        var db = HostileJobDatabases.Healthy(HostileJobDatabases.Folder("clean"));
        File.Exists(db + "-wal").Should().BeFalse("the last close folds the log into the database");

        for (var i = 0; i < 3; i++)
        {
            using var store = JobStore.Open(db);
            store.Get(1).Should().NotBeNull();
        }
    }

    [Fact]
    public void A_torn_tail_of_an_uncommitted_write_is_not_damage()
    {
        var db = HostileJobDatabases.CrashImage(HostileJobDatabases.Folder("torn"));
        using (var f = new FileStream(db + "-wal", FileMode.Append))
        {
            f.Write(new byte[1000]); // half a frame: a writer killed mid-write
        }

        using var store = JobStore.Open(db);
        store.Get(1)!.Checkpoint.Should().Be(HostileJobDatabases.Checkpoint);
    }

    [Fact]
    public void A_folder_where_the_database_should_be_is_named()
    {
        var db = HostileJobDatabases.Folder("isdir");

        var e = FluentActions.Invoking(() => JobStore.Open(db)).Should().Throw<JobStoreException>().Which;

        e.Problem.Should().Be(JobStoreProblem.Unavailable);
        e.Message.Should().Be($"{db}: is a folder, not a job database");
        Directory.Exists(db).Should().BeTrue();
    }
}
