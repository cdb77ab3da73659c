using System.Globalization;
using System.Text.Json;

namespace PmacStream.WinForms;

/// <summary>
/// The automated UI test's link to the running form (<c>--ui-test DIR</c>): on a UI-thread timer it writes
/// <c>DIR/state.json</c> (replaced whole, never half-written) and carries out the commands the test drops as
/// <c>DIR/cmd-NNNNNN.txt</c>, in order, one per tick. Off unless the option is given.
/// </summary>
internal sealed class UiTestChannel : IDisposable
{
    private readonly MainForm _form;
    private readonly string _directory;
    private readonly System.Windows.Forms.Timer _timer = new() { Interval = 100 };
    private long _sequence;
    private int _lastCommand;
    private string? _commandError;
    private bool _inCommand;

    /// <summary>Starts writing snapshots of <paramref name="form"/> into <paramref name="directory"/>.</summary>
    public UiTestChannel(MainForm form, string directory)
    {
        _form = form;
        _directory = directory;
        Directory.CreateDirectory(directory);
        _timer.Tick += (_, _) => Tick();
        _timer.Start();
    }

    /// <inheritdoc />
    public void Dispose() => _timer.Dispose();

    private void Tick()
    {
        // One command per tick, so each takes effect on the screen before the next is read.
        // A command that opens a modal box keeps running in its loop, where this timer still ticks: snapshots go on,
        // the next command waits.
        var next = _inCommand ? null : Directory.EnumerateFiles(_directory, "cmd-*.txt").Order(StringComparer.Ordinal).FirstOrDefault();
        if (next is not null)
        {
            var command = File.ReadAllText(next).Trim();
            File.Delete(next);
            _lastCommand = int.Parse(Path.GetFileNameWithoutExtension(next)["cmd-".Length..], CultureInfo.InvariantCulture);
            _commandError = null;
            _inCommand = true;
            try
            {
                _form.RunScripted(command);
            }
            catch (Exception e) when (e is ArgumentException or InvalidOperationException or FormatException or OverflowException)
            {
                _commandError = e.Message;
            }
            finally
            {
                _inCommand = false;
            }
        }

        if (_form.IsDisposed)
        {
            return;
        }

        var snapshot = _form.Snapshot(++_sequence, _lastCommand, _commandError);
        var temp = Path.Combine(_directory, "state.json.tmp");
        File.WriteAllText(temp, JsonSerializer.Serialize(snapshot, UiSnapshotJson.Default.UiSnapshot));
        File.Move(temp, Path.Combine(_directory, "state.json"), overwrite: true);
    }
}
