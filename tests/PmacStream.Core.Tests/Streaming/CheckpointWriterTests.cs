using PmacStream.Streaming;

namespace PmacStream.Core.Tests.Streaming;

public class CheckpointWriterTests
{
    private static Checkpoint At(int chunk, int line) =>
        new(line, chunk, new StreamPosition(chunk + 1, 0), true, chunk, SessionState.Running, DateTimeOffset.UnixEpoch);

    [Fact]
    public void The_first_checkpoint_in_every_chunk_is_durable_the_others_only_when_asked()
    {
        var sink = new RecordingSink();
        var now = At(1, 10);
        var writer = new CheckpointWriter(sink, () => now);

        writer.Save(durable: false);
        now = At(1, 11);
        writer.Save(durable: false);
        writer.Save(durable: true);
        now = At(2, 1001);
        writer.Save(durable: false);
        now = At(2, 1002);
        writer.Save(durable: false);

        sink.Saved.Select(s => (s.Checkpoint.LastExecutedLine, s.Durable)).Should().Equal(
            (10, true), (11, false), (11, true), (1001, true), (1002, false));
    }

    [Fact]
    public void Without_a_sink_no_checkpoint_is_even_taken()
    {
        var taken = 0;
        var writer = new CheckpointWriter(null, () =>
        {
            taken++;
            return At(1, 1);
        });

        writer.Save(durable: true);
        writer.RecordStart(new JobStart(5, null, "P501"));
        taken.Should().Be(0);
    }

    [Fact]
    public void The_start_is_recorded_in_the_sink()
    {
        var sink = new RecordingSink();
        new CheckpointWriter(sink, () => At(1, 1)).RecordStart(new JobStart(5, ["G90"], "P501"));
        sink.Start.Should().NotBeNull();
        sink.Start!.FromLine.Should().Be(5);
        sink.Start.Preamble.Should().Equal("G90");
    }

    private sealed class RecordingSink : ICheckpointSink
    {
        public List<(Checkpoint Checkpoint, bool Durable)> Saved { get; } = [];

        public JobStart? Start { get; private set; }

        public void Save(Checkpoint checkpoint, bool durable) => Saved.Add((checkpoint, durable));

        public void RecordStart(JobStart start) => Start = start;
    }
}
