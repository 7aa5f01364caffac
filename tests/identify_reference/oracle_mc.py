"""Fixed-design Monte Carlo of the ring-down oracle (issue 42, tests/identify_coverage.md).

A numpy/scipy re-implementation of tests/identify_reference/mod.rs (ring-down
records only; positions from numpy, not the crate RNG) and of the oracle fit
(weighted least squares at the true structure, exact weights 1/sigma(t),
started at the true poles); with a fourth argument `complex` or `magnitude`,
the same for the frequency records of mod.rs (1 500 log-spaced points over
[0.5 w1, 1.15 w3], the oracle fit at every true mode, in band or above, and
the relaxation pole, no residual terms, exact weights). For each of ND designs (support cycling, sensor
positions uniform in (0.02, 0.98)) it draws R noise realisations and prints,
per visible mode (ring-down: matched-filter SNR >= 20; sweep: the
generator's rule, >= 20 noise sd at resonance and >= 3 points in the
half-power band), the mean, sd and 95 % coverage of
z = (estimate - truth)/reported sd. Usage: python3 oracle_mc.py ND R prop|add [time|complex|magnitude]
"""
import sys
from scipy.optimize import least_squares
import numpy as np
PI=np.pi
ZETA=[0.012,0.006,0.009,0.015,0.02,0.01,0.012,0.015]
def beta(sup,n):
    if sup=='ss': return n*PI
    if sup=='cc': g=lambda b: np.cos(b)-1/np.cosh(b); lo,hi=n*PI,(n+1)*PI
    else: g=lambda b: np.cos(b)+1/np.cosh(b); lo,hi=(n-1)*PI,n*PI
    a,b=lo+1e-12,hi-1e-12; ga=g(a)
    for _ in range(200):
        m=0.5*(a+b)
        if (g(m)>0)==(ga>0): a=m
        else: b=m
    return 0.5*(a+b)
def shape(sup,n,x):
    b=beta(sup,n)
    if sup=='ss': return np.sin(b*x)
    s=(np.cosh(b)-np.cos(b))/(np.sinh(b)-np.sin(b)) if sup=='cc' else (np.sinh(b)-np.sin(b))/(np.cosh(b)+np.cos(b))
    return np.cosh(b*x)-np.cos(b*x)-s*(np.sinh(b*x)-np.sin(b*x))
def mass(sup,n):
    x=np.linspace(0,1,2001); f=shape(sup,n,x)**2
    return np.trapezoid(f,x)
def beam(sup,x_in,x_out,w1=2*PI*1e4,nm=5,relax=0.3):
    b1=beta(sup,1); modes=[]
    for n in range(1,nm+1):
        w=w1*(beta(sup,n)/b1)**2
        g=shape(sup,n,x_in)*shape(sup,n,x_out)/mass(sup,n)*1e-9*w1*w1
        modes.append((w,ZETA[n-1],g))
    gam=0.3*w1
    return modes,gam,relax*1e-9*gam
def ringdown(modes,gam,B,band=3,n=4000):
    top=modes[band-1][0]; nyq=8*top/2; dt=PI/nyq; cut=0.8*nyq
    t=np.arange(n)*dt
    keep=[m for m in modes if m[0]<cut]
    y=B*np.exp(-gam*t)
    for w,z,g in keep:
        wd=w*np.sqrt(1-z*z)
        y=y+g*np.exp(-z*w*t)*np.sin(wd*t)/wd
    return t,dt,keep,y
def model(th,x,nm):
    y=np.zeros_like(x); J=np.zeros((len(x),len(th)))
    for r in range(nm):
        s,wd,C,S=th[4*r:4*r+4]
        e=np.exp(-s*x); c=np.cos(wd*x); sn=np.sin(wd*x)
        v=e*(C*c+S*sn); y+=v
        J[:,4*r]=-x*v; J[:,4*r+1]=e*x*(-C*sn+S*c); J[:,4*r+2]=e*c; J[:,4*r+3]=e*sn
    o=4*nm; g,B,c0=th[o:o+3]
    e=np.exp(-g*x); y+=B*e+c0; J[:,o]=-x*B*e; J[:,o+1]=e; J[:,o+2]=1
    return y,J
def truth_theta(keep,gam,B,dt,peak):
    th=[]
    for w,z,g in keep:
        wd=w*np.sqrt(1-z*z); th+= [z*w*dt/PI, wd*dt/PI, 0.0, g/wd/peak]
    th+=[gam*dt/PI,B/peak,0.0]
    return np.array(th)
def wz(th,r,cov):
    s,wd=th[4*r],th[4*r+1]; w=np.hypot(s,wd); z=s/w
    gw=np.array([s/w,wd/w]); gz=np.array([wd*wd/w**3,-s*wd/w**3])
    C=cov[4*r:4*r+2,4*r:4*r+2]
    return w,np.sqrt(gw@C@gw),z,np.sqrt(gz@C@gz)

def sweep_model(th,s,nm,magnitude):
    """H(s) = sum A/(s-p) + conj(A)/(s-conj(p)) + B/(s+g) and dH/dtheta (complex)."""
    H=np.zeros(len(s),complex); D=np.zeros((len(s),len(th)),complex)
    for r in range(nm):
        sg,wd,a,b=th[4*r:4*r+4]; p=-sg+1j*wd; A=a+1j*b
        u=1/(s-p); v=1/(s-np.conj(p))
        H+=A*u+np.conj(A)*v
        du=A*u*u; dv=np.conj(A)*v*v
        D[:,4*r]=-du-dv; D[:,4*r+1]=1j*du-1j*dv; D[:,4*r+2]=u+v; D[:,4*r+3]=1j*u-1j*v
    o=4*nm; g,Bb=th[o:o+2]; u=1/(s+g)
    H+=Bb*u; D[:,o]=-Bb*u*u; D[:,o+1]=u
    return H,D
def sweep_mc(ND,R,kind,rec,prng):
    rows=[]
    for d in range(ND):
        sup=['ss','cc','cl'][d%3]; xi,xo=prng.uniform(0.02,0.98,2)
        modes,gam,B=beam(sup,xi,xo)
        lo,hi=0.5*modes[0][0],1.15*modes[2][0]
        w=np.exp(np.linspace(np.log(lo),np.log(hi),1500))
        H=B/(gam+1j*w)
        for wm,zm,g in modes: H=H+g/(wm*wm-w*w+2j*zm*wm*w)
        peak=np.abs(H).max()
        sd=np.sqrt((1e-4*peak)**2+(0.01*np.abs(H))**2) if kind=='prop' else np.full(len(w),5e-3*peak)
        vis=[]
        for k,(wm,zm,g) in enumerate(modes):
            s_=abs(g/(2j*zm*wm*wm)); sdm=np.sqrt((1e-4*peak)**2+(0.01*s_)**2) if kind=='prop' else 5e-3*peak
            if wm<=hi and s_>=20*sdm and np.sum(np.abs(w-wm)<=zm*wm)>=3: vis.append((k,s_/sdm,np.sum(np.abs(w-wm)<=zm*wm)))
        wref=1.5*hi; s=1j*w/wref; nm=len(modes)
        th0=[]
        for wm,zm,g in modes:
            p=(-zm*wm+1j*wm*np.sqrt(1-zm*zm))/wref; A=g/(wref*wref*peak)/(2j*p.imag)
            th0+=[-p.real,p.imag,A.real,A.imag]
        th0=np.array(th0+[gam/wref,B/(wref*peak)])
        wt=sd[0]/sd
        rng=np.random.default_rng(2000+d)
        Z=[]
        for rep in range(R):
            if rec=='complex':
                y=(H+sd*(rng.standard_normal(len(w))+1j*rng.standard_normal(len(w))))/peak
                def f(th):
                    h=sweep_model(th,s,nm,False)[0]-y; return np.concatenate([h.real*wt,h.imag*wt])
                def jf(th):
                    D=sweep_model(th,s,nm,False)[1]; return np.vstack([D.real*wt[:,None],D.imag*wt[:,None]])
            else:
                y=np.abs(np.abs(H)+sd*rng.standard_normal(len(w)))/peak
                def f(th):
                    return (np.abs(sweep_model(th,s,nm,True)[0])-y)*wt
                def jf(th):
                    h,D=sweep_model(th,s,nm,True); return (np.conj(h)[:,None]*D).real/np.abs(h)[:,None]*wt[:,None]
            res=least_squares(f,th0,jac=jf,method='lm',xtol=1e-15,ftol=1e-15,gtol=1e-15,x_scale='jac')
            r=res.fun; J=res.jac; m,p_=J.shape
            cov=(r@r/(m-p_))*np.linalg.pinv(J.T@J)
            row=[]
            for k,snr,band in vis:
                wm,zm,g=modes[k]; W,Ws,Zh,Zs=wz(res.x,k,cov)
                row+=[(W*wref-wm)/(Ws*wref),(Zh-zm)/Zs]
            Z.append(row)
        Z=np.array(Z)
        for i,(k,snr,band) in enumerate(vis):
            for j in range(2):
                c=Z[:,2*i+j]
                rows.append((d,k+1,j,snr,band,c.mean(),c.std(),np.mean(np.abs(c)<=1.96)))
                flag='  <<' if c.std()>1.3 or abs(c.mean())>0.5 else ''
                print(f"d{d} {sup} x {xi:.2f} {xo:.2f} mode{k+1} {'wz'[j]} snr {snr:.0f} band {band} mean {c.mean():+.2f} sd {c.std():.2f} cov {np.mean(np.abs(c)<=1.96):.2f}{flag}",flush=True)
    a=np.array([r[3:] for r in rows],dtype=float)
    print("pooled coverage", a[:,4].mean(), "mean per-cell sd of z", a[:,3].mean(), "cells", len(a), "intervals", len(a)*R)
ND=int(sys.argv[1]); R=int(sys.argv[2]); kind=sys.argv[3]
prng=np.random.default_rng(7)
if len(sys.argv)>4 and sys.argv[4] in ('complex','magnitude'):
    sweep_mc(ND,R,kind,sys.argv[4],prng)
    sys.exit(0)
rows=[]
for d in range(ND):
    sup=['ss','cc','cl'][d%3]; xi,xo=prng.uniform(0.02,0.98,2)
    modes,gam,B=beam(sup,xi,xo)
    t,dt,keep,clean=ringdown(modes,gam,B)
    peak=np.abs(clean).max()
    sd=np.sqrt((1e-4*peak)**2+(0.01*clean)**2) if kind=='prop' else np.full_like(clean,5e-3*peak)
    x=PI*np.arange(len(t)); nm=len(keep)
    # matched filter SNR per mode
    snr=[]
    for wt,zt,g in keep:
        wd=wt*np.sqrt(1-zt*zt); v=g/wd*np.exp(-zt*wt*t)*np.sin(wd*t); snr.append(np.sqrt(np.sum((v/sd)**2)))
    th0=truth_theta(keep,gam,B,dt,peak); w=sd[0]/sd
    rng=np.random.default_rng(1000+d)
    Z=[]
    for rep in range(R):
        y=(clean+sd*rng.standard_normal(len(t)))/peak
        f=lambda th: (model(th,x,nm)[0]-y)*w
        jf=lambda th: model(th,x,nm)[1]*w[:,None]
        res=least_squares(f,th0,jac=jf,method='lm',xtol=1e-15,ftol=1e-15,gtol=1e-15,x_scale='jac')
        r=res.fun; J=res.jac; m,p=J.shape
        cov=(r@r/(m-p))*np.linalg.inv(J.T@J)
        row=[]
        for k,(wt,zt,g) in enumerate(keep):
            W,Ws,Zh,Zs=wz(res.x,k,cov)
            row+=[(W*PI/dt-wt)/(Ws*PI/dt),(Zh-zt)/Zs]
        Z.append(row)
    Z=np.array(Z)
    for k in range(nm):
        if snr[k]<20: continue
        for j in range(2):
            c=Z[:,2*k+j]
            rows.append((d,sup,k+1,j,snr[k],c.mean(),c.std(),np.mean(np.abs(c)<=1.96)))
            flag='  <<' if c.std()>1.3 or abs(c.mean())>0.5 else ''
            print(f"d{d} {sup} x {xi:.2f} {xo:.2f} mode{k+1} {'wz'[j]} snr {snr[k]:.0f} mean {c.mean():+.2f} sd {c.std():.2f} cov {np.mean(np.abs(c)<=1.96):.2f}{flag}",flush=True)
rows=np.array([r[2:] for r in rows],dtype=float)
print("pooled coverage", rows[:,5].mean(), "n", len(rows))
