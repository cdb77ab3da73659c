using System.Text;
using PmacStream.Pmac;

namespace PmacStream.Core.Tests.Streaming;

/// <summary>Answers each command with a scripted text (values separated by CR); <c>ERRnnn</c> becomes an error reply.</summary>
internal sealed class ScriptedPort(Func<string, string> reply) : IPmacPortEndpoint
{
    public List<string> Sent { get; } = [];

    public byte[] Execute(string commandLine)
    {
        Sent.Add(commandLine);
        var text = reply(commandLine);
        return text.StartsWith("ERR", StringComparison.Ordinal)
            ? Encoding.ASCII.GetBytes("\a" + text + "\r")
            : Encoding.ASCII.GetBytes(text.Length == 0 ? "\x06" : text + "\r\x06");
    }

    public void Flush()
    {
    }

    public byte[] Control(char control) => [];
}
