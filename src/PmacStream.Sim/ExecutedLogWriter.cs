using System.Globalization;
using System.Text;

namespace PmacStream.Sim;

/// <summary>
/// The executed-move log as CSV (<c>sequence,line,start_s,end_s,x,y,z,a,b,c,kind,block</c>: the end of each move in the
/// coordinate system's base (machine) coordinates, after the axis transformation matrix; <c>block</c> 1 for the move that
/// starts a block, <see cref="ExecutedMove.BlockStart"/>), written as moves finish rather than
/// kept in memory: rows go to <c>PATH.tmp</c>, which <see cref="Complete"/> (or <see cref="Dispose"/>) renames to
/// <c>PATH</c>. A host killed meanwhile leaves the rows written so far in <c>PATH.tmp</c>. Thread-safe.
/// </summary>
public sealed class ExecutedLogWriter : IDisposable
{
    /// <summary>The CSV header line.</summary>
    public const string Header = "sequence,line,start_s,end_s,x,y,z,a,b,c,kind,block";

    private readonly object _lock = new();
    private readonly string _temp;
    private PmacSimulator? _attached;
    private StreamWriter? _writer;

    /// <summary>Starts a log at <paramref name="path"/> (its folder must exist).</summary>
    public ExecutedLogWriter(string path)
    {
        Path = System.IO.Path.GetFullPath(path);
        _temp = Path + ".tmp";
        _writer = new StreamWriter(_temp, false, new UTF8Encoding(false), 1 << 16) { NewLine = "\n" };
        _writer.WriteLine(Header);
    }

    /// <summary>The log's final path.</summary>
    public string Path { get; }

    /// <summary>Rows written.</summary>
    public long Rows { get; private set; }

    /// <summary>Writes the whole log of <paramref name="moves"/> at once.</summary>
    public static void WriteAll(string path, IEnumerable<ExecutedMove> moves)
    {
        ArgumentNullException.ThrowIfNull(moves);
        using var log = new ExecutedLogWriter(path);
        foreach (var m in moves)
        {
            log.Write(m);
        }
    }

    /// <summary>Writes every move <paramref name="simulator"/> finishes from now on, until <see cref="Complete"/>.</summary>
    public ExecutedLogWriter Attach(PmacSimulator simulator)
    {
        ArgumentNullException.ThrowIfNull(simulator);
        lock (_lock)
        {
            if (_attached is not null)
            {
                throw new InvalidOperationException("already attached to a simulator");
            }

            _attached = simulator;
            simulator.MoveExecuted += Write;
        }

        return this;
    }

    /// <summary>Appends one row.</summary>
    public void Write(ExecutedMove m)
    {
        lock (_lock)
        {
            ObjectDisposedException.ThrowIf(_writer is null, this);
            _writer.WriteLine(string.Create(CultureInfo.InvariantCulture, $"{m.Sequence},{m.SourceLine},{m.StartTime:0.######},{m.EndTime:0.######},{m.X:0.######},{m.Y:0.######},{m.Z:0.######},{m.Rotary.A:0.######},{m.Rotary.B:0.######},{m.Rotary.C:0.######},{m.Kind},{(m.BlockStart ? 1 : 0)}"));
            Rows++;
        }
    }

    /// <summary>Stops listening, closes the file and moves it into place. Later calls do nothing.</summary>
    public void Complete()
    {
        lock (_lock)
        {
            if (_attached is { } sim)
            {
                sim.MoveExecuted -= Write;
                _attached = null;
            }

            if (_writer is null)
            {
                return;
            }

            _writer.Dispose();
            _writer = null;
            File.Move(_temp, Path, overwrite: true);
        }
    }

    /// <summary>Completes the log: what ran is kept, even when the host stops early.</summary>
    public void Dispose() => Complete();
}
