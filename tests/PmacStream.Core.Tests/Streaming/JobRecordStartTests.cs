using Microsoft.Data.Sqlite;
using PmacStream.Streaming;

namespace PmacStream.Core.Tests.Streaming;

public class JobRecordStartTests
{
    /// <summary>The schema before the line probe, the preamble and cp_loaded were recorded.</summary>
    private const string OldSchema = """
        CREATE TABLE jobs (
          id INTEGER PRIMARY KEY AUTOINCREMENT, created TEXT NOT NULL, program_path TEXT NOT NULL, program_sha256 TEXT NOT NULL,
          manifest_path TEXT NOT NULL, strategy TEXT NOT NULL, connection TEXT NOT NULL, from_line INTEGER,
          message TEXT NOT NULL DEFAULT '', cp_time TEXT, cp_state TEXT, cp_last_line INTEGER, cp_chunk INTEGER,
          cp_next_chunk INTEGER, cp_next_line INTEGER, cp_next_exact INTEGER, cp_chunks_downloaded INTEGER, cp_started INTEGER);
        INSERT INTO jobs (created, program_path, program_sha256, manifest_path, strategy, connection, from_line, message,
          cp_time, cp_state, cp_last_line, cp_chunk, cp_next_chunk, cp_next_line, cp_next_exact, cp_chunks_downloaded, cp_started)
        VALUES ('2026-01-01T00:00:00.0000000+00:00', '/x/a.nc', 'aa', '/x/m/manifest.json', 'chunk', 'sim', 40, 'link lost',
          '2026-01-01T00:01:00.0000000+00:00', 'Faulted', 120, 2, 3, 5, 0, 2, 1);
        """;

    [Fact]
    public void An_old_job_database_stays_readable_and_gains_the_new_columns_with_defaults()
    {
        using var temp = new TestFolder("oldjobs");
        var db = Path.Combine(temp.Path, "jobs.db");
        using (var raw = new SqliteConnection($"Data Source={db};Pooling=False"))
        {
            raw.Open();
            using var cmd = raw.CreateCommand();
            cmd.CommandText = OldSchema;
            cmd.ExecuteNonQuery();
        }

        using (var store = JobStore.Open(db))
        {
            var old = store.Get(1)!;
            old.FromLine.Should().Be(40);
            old.LineProbeVariable.Should().Be("P501", "jobs of older versions ran with the default probe");
            old.Preamble.Should().BeNull();
            old.Checkpoint!.Loaded.Should().BeTrue("an old checkpoint is one of a loaded start");
            old.Checkpoint.Next.Should().Be(new StreamPosition(3, 5));

            var id = store.CreateJob("b.nc", "bb", "m/manifest.json", StrategyKind.Pr, "sim", null, "P777");
            store.Get(id)!.LineProbeVariable.Should().Be("P777");
            store.RecordStart(id, new JobStart(88, ["G90 G0 Z10", "X1 Y2"], null));
            var cp = new Checkpoint(0, 3, new StreamPosition(3, 7), true, 0, SessionState.Idle, DateTimeOffset.UnixEpoch, Started: false, Loaded: false);
            store.SaveCheckpoint(id, cp, durable: true);
        }

        // Opening again finds the columns there (the migration runs once) and reads back what was recorded.
        using (var store = JobStore.Open(db))
        {
            var job = store.Get(2)!;
            job.FromLine.Should().Be(88);
            job.Preamble.Should().Equal("G90 G0 Z10", "X1 Y2");
            job.LineProbeVariable.Should().BeNull("the start ran without a probe");
            job.Checkpoint!.Loaded.Should().BeFalse();
            job.Checkpoint.Started.Should().BeFalse();
            store.Get(1)!.LineProbeVariable.Should().Be("P501");
        }
    }

    [Fact]
    public async Task A_start_records_itself_before_sending_and_its_checkpoints_say_loaded_only_once_the_load_completed()
    {
        using var temp = new TestFolder("startrec");
        var program = FakeSplit.Write(temp.Path, FakeSplit.Program(300, 5), 60);
        var rig = new FakeRig(program, new StreamingOptions { LineProbeVariable = "P640" });
        await rig.Session.StartAsync();
        rig.Sink.Start!.FromLine.Should().BeNull();
        rig.Sink.Start.LineProbeVariable.Should().Be("P640");
        rig.Sink.Start.Preamble.Should().BeNull();
        rig.Sink.Last!.Loaded.Should().BeTrue();
        rig.Sink.Last.Started.Should().BeTrue();

        // A record whose checkpoint was taken while loading: the checkpoint alone cannot be resumed.
        var loading = rig.Sink.Last with { Loaded = false, Started = false };
        rig.Session = rig.NewSession();
        var act = () => rig.Session.ResumeAsync(loading);
        (await act.Should().ThrowAsync<InvalidOperationException>()).WithMessage("*broke off while loading*");
        rig.Session.State.Should().Be(SessionState.Idle);

        // A record of an older version (no preamble) of a start from a line: restart with a new plan instead.
        var record = rig.Sink.Record() with { FromLine = 120, Preamble = null, Checkpoint = loading };
        act = () => rig.Session.ResumeAsync(record);
        (await act.Should().ThrowAsync<InvalidOperationException>()).WithMessage("*holds no preamble*restart from line 120*");
    }
}
